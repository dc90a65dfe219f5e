// `megavox mask train | apply`: histogram models from hand-made masks, and GrabCut masks of photographs and
// range maps (box, seed map and model starts; min-cuts on the device; median and erosion as kernels).
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_common.h"
#include "profile_report.h"
#include "io/image_reader.h"
#include "io/mvm_file.h"
#include "io/output_path.h"
#include "io/png_grey.h"
#include "megavox/error.h"
#include "megavox/mask.h"
#include "megavox/render.h"

namespace fs = std::filesystem;

namespace mv::cli {

CLI::Option* add_min_cut_solver_option(CLI::App& cmd, std::string& name) {
  return cmd
      .add_option("--min-cut-solver", name,
                  "How the device finds each min-cut (every solver gives the same cut, so the same masks):\n"
                  "auto (default: regions where each work-item is a CPU thread (PoCL), push-relabel on SIMT and\n"
                  "massively parallel devices), regions (Boykov-Kolmogorov over regions side by side, merged 2 x 2;\n"
                  "where lanes run in lock step, a region per lane, then push-relabel across their seams),\n"
                  "push-relabel (tiled push-relabel with a breadth-first global relabel, every tile at once)")
      ->check(CLI::IsMember({"auto", "regions", "push-relabel"}))
      ->capture_default_str();
}

MinCutSolver min_cut_solver(const std::string& name) {
  const auto s = parse_min_cut_solver(name);
  if (!s) throw CodedError(ErrorCode::invalid_argument, "--min-cut-solver: '" + name + "' (auto, regions, push-relabel)");
  return *s;
}

namespace {

MaskBox parse_rect(const std::string& text) {
  std::istringstream in(text);
  long v[4];
  char c[3] = {};
  if (!(in >> v[0] >> c[0] >> v[1] >> c[1] >> v[2] >> c[2] >> v[3]) || c[0] != ',' || c[1] != ',' || c[2] != ',' ||
      !in.eof() || v[0] < 0 || v[1] < 0 || v[2] <= 0 || v[3] <= 0 || v[0] > 1 << 30 || v[1] > 1 << 30 ||
      v[2] > 1 << 30 || v[3] > 1 << 30)
    throw CodedError(ErrorCode::invalid_argument,
                     "rect wants X,Y,W,H (four whole numbers, W and H above 0), got '" + text + "'");
  return MaskBox{uint32_t(v[0]), uint32_t(v[1]), uint32_t(v[2]), uint32_t(v[3])};
}

struct Job {
  std::string image, rect, seeds, model;
  std::string where;  // a list's line, "LIST:LINE", that named the image; empty: the command line
};

// Runs `body`; an error it throws comes out prefixed with `where` ("FILE:LINE: ..."), its code kept.
template <class F>
auto at(const std::string& where, F&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    if (where.empty()) throw;
    throw CodedError(classify(e), where + ": " + error_message(e), error_settings(e));
  }
}

// `--list FILE`: one image a line, `IMAGE [rect=X,Y,W,H] [seeds=PATH] [model=PATH]`; relative paths are
// relative to the list's folder; blank lines and lines starting with # are skipped.
std::vector<Job> read_list(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open list '" + path + "'");
  const fs::path base = fs::path(path).parent_path();
  auto resolve = [&](const std::string& p) { return fs::path(p).is_absolute() ? p : (base / p).string(); };
  std::vector<Job> jobs;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string w;
    if (!(words >> w) || w[0] == '#') continue;
    Job j{resolve(w), "", "", "", path + ":" + std::to_string(number)};
    while (words >> w) {
      const auto eq = w.find('=');
      const std::string key = w.substr(0, eq), value = eq == std::string::npos ? "" : w.substr(eq + 1);
      if (key == "rect" && !value.empty()) j.rect = value;
      else if (key == "seeds" && !value.empty()) j.seeds = resolve(value);
      else if (key == "model" && !value.empty()) j.model = resolve(value);
      else
        throw CodedError(ErrorCode::invalid_argument,
                         j.where + ": '" + w + "' (rect=X,Y,W,H, seeds=PATH or model=PATH expected)");
    }
    jobs.push_back(j);
  }
  if (jobs.empty()) throw CodedError(ErrorCode::invalid_argument, path + ": the list names no image");
  return jobs;
}

// The image with the background dimmed toward blue and the mask's rim in yellow: for a person to check.
Image overlay(const RasterImage& img, const std::vector<uint8_t>& mask) {
  Image out;
  out.width = img.width;
  out.height = img.height;
  out.rgb.resize(size_t{img.width} * img.height * 3);
  const double to255 = 255.0 / std::max<uint32_t>(img.max_value, 1);
  for (uint32_t y = 0; y < img.height; ++y)
    for (uint32_t x = 0; x < img.width; ++x) {
      const size_t i = size_t{y} * img.width + x;
      const bool fg = mask[i] != 0;
      bool rim = false;
      if (fg)
        for (int d = 0; d < 4 && !rim; ++d) {
          const long nx = long{x} + (d == 0) - (d == 1), ny = long{y} + (d == 2) - (d == 3);
          rim = nx < 0 || ny < 0 || nx >= long{img.width} || ny >= long{img.height} ||
                mask[size_t(ny) * img.width + size_t(nx)] == 0;
        }
      for (int c = 0; c < 3; ++c) {
        const double v = img.samples[i * img.channels + (img.channels == 3 ? c : 0)] * to255;
        const double tint[3] = {20, 30, 110};
        double o = fg ? v : 0.35 * v + 0.65 * tint[c];
        if (rim) o = c == 2 ? 0 : 255;
        out.rgb[i * 3 + c] = static_cast<uint8_t>(std::lround(std::clamp(o, 0.0, 255.0)));
      }
    }
  return out;
}

struct ApplyArgs {
  std::vector<std::string> images;
  std::string output, rect, seeds, model, list, solver = "auto";
  uint32_t iterations = 5, erode = 2;
  bool no_post = false, overlay = false, json = false, quiet = false, no_clobber = false;
};

// Every mask (and overlay) path, resolved and checked before any image is read: not an input, not a
// FIFO or device, no two images writing the same name.
std::vector<std::pair<std::string, std::string>> resolve_masks(const ApplyArgs& a, const std::vector<Job>& jobs) {
  io::check_output_folder(a.output);
  std::vector<std::string> inputs = {a.list};
  for (const Job& j : jobs) inputs.insert(inputs.end(), {j.image, j.seeds, j.model});
  const bool folder_exists = fs::is_directory(a.output);
  std::map<std::string, std::string> written;  // output -> the image it is of
  std::vector<std::pair<std::string, std::string>> out;
  auto check = [&](const Job& j, const std::string& name) {
    const std::string path = (fs::path(a.output) / name).string();
    auto [it, fresh] = written.emplace(path, j.image);
    if (!fresh)
      throw Error("mask apply: '" + it->second + "' and '" + j.image + "' would both write '" + path +
                  "' (masks are named by the image's basename); mask them into separate folders");
    return folder_exists ? io::resolve_output({path, io::OutputKind::kFile, "png", inputs, 0, a.no_clobber}) : path;
  };
  for (const Job& j : jobs) {
    const std::string stem = fs::path(j.image).stem().string();
    const std::string mask = check(j, stem + ".png");
    out.emplace_back(mask, a.overlay ? check(j, stem + ".overlay.png") : std::string());
  }
  return out;
}

void add_mask_apply(CLI::App& mask, const GlobalOptions& g) {
  auto a = std::make_shared<ApplyArgs>();
  auto* cmd = mask.add_subcommand(
      "apply",
      "Mask photographs and range maps (PNG, JPEG, PPM, PGM; 8- or 16-bit) with GrabCut: 5-component colour\n"
      "mixtures per side, 8-neighbour contrast-sensitive smoothness (gamma 50), min-cuts on the device, then a\n"
      "5x5 median and an octagon erosion. Writes OUTDIR/<image basename>.png (0 background, 255 foreground).\n"
      "Starts (combine them): --rect (outside sure background, inside probable foreground), --seeds (a trimap\n"
      "or strokes: 0 sure bg, 64 probable bg, 128 unknown, 192 probable fg, 255 sure fg; it overrides the rest\n"
      "where it is not 128), --model (a `mask train` histogram, probable foreground above 0.5).\n"
      "Examples:\n"
      "  megavox mask apply photo.jpg --rect 40,30,300,200 -o masks/ --overlay\n"
      "  megavox mask apply scans/*.pgm --model statue.mvm -o masks/ --json\n"
      "  megavox mask apply --list batch.txt -o masks/   (lines: IMAGE [rect=X,Y,W,H] [seeds=PATH] [model=PATH])");
  cmd->add_option("images", a->images, "Images to mask");
  cmd->add_option("-o,--output", a->output, "Folder for the masks (made if missing)")->required();
  cmd->add_option("--rect", a->rect, "Box X,Y,W,H in pixels: outside is sure background");
  cmd->add_option("--seeds", a->seeds, "Seed map (trimap or strokes), an 8-bit grey image of the image's size");
  cmd->add_option("--model", a->model, "Histogram model (.mvm) from `megavox mask train`");
  cmd->add_option("--list", a->list, "Batch file: one image a line with its own rect=, seeds=, model=");
  cmd->add_option("--iterations", a->iterations, "GrabCut iterations at most (default 5; stops when nothing changes)")
      ->check(CLI::Range(1, 100));
  cmd->add_flag("--no-post", a->no_post, "Skip the median and the erosion");
  cmd->add_option("--erode", a->erode, "Erosion octagon radius in pixels (default 2, 0 = none, at most 32)")
      ->check(CLI::Range(0, 32));
  add_min_cut_solver_option(*cmd, a->solver);
  cmd->add_flag("--overlay", a->overlay, "Also write OUTDIR/<basename>.overlay.png: the mask over the image");
  cmd->add_flag("--json", a->json, "Print per-image statistics as JSON");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  add_no_clobber_flag(*cmd, a->no_clobber);
  cmd->callback([a, &g] {
    std::vector<Job> jobs;
    if (!a->list.empty()) jobs = read_list(a->list);
    for (const auto& im : a->images) jobs.push_back({im, "", "", "", ""});
    if (jobs.empty())
      throw CodedError(ErrorCode::invalid_argument, "mask apply: no image given (IMAGE... or --list FILE)");
    for (Job& j : jobs) {  // the command line's starts apply where a list line says nothing
      if (j.rect.empty()) j.rect = a->rect;
      if (j.seeds.empty()) j.seeds = a->seeds;
      if (j.model.empty()) j.model = a->model;
    }
    const auto outputs = resolve_masks(*a, jobs);
    std::error_code ec;
    fs::create_directories(a->output, ec);
    if (!fs::is_directory(a->output))
      throw Error("cannot make the output folder '" + a->output + "': " + ec.message());
    auto dev = open_device(g);
    ParallelismMeter meter(*dev);
    if (g.profile) meter.start();
    double io_seconds = 0;  // reading images and models, writing masks and overlays
    auto timed_io = [&](auto&& body) {
      const auto t = std::chrono::steady_clock::now();
      struct Lap {
        std::chrono::steady_clock::time_point t;
        double& sum;
        ~Lap() { sum += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); }
      } lap{t, io_seconds};
      return body();
    };
    const bool bar = !a->quiet && !a->json && isatty(STDERR_FILENO);
    Progress progress = progress_bar(bar);
    std::map<std::string, MaskModel> models;
    nlohmann::json report = nlohmann::json::array();
    for (size_t k = 0; k < jobs.size(); ++k) {
      const Job& j = jobs[k];
      const auto start_time = std::chrono::steady_clock::now();
      const RasterImage img = at(j.where, [&] { return timed_io([&] { return io::read_image(j.image); }); });
      MaskStart start;
      at(j.where, [&] {
        if (!j.rect.empty()) start.box = parse_rect(j.rect);
        if (!j.seeds.empty()) start.seeds = io::read_seed_map(j.seeds, img.width, img.height);
        if (!j.model.empty()) {
          if (!models.count(j.model)) models.emplace(j.model, timed_io([&] { return io::read_mvm(j.model); }));
          start.model = &models.at(j.model);
        }
      });
      MaskOptions o;
      o.iterations = a->iterations;
      o.post = !a->no_post;
      o.erode_radius = a->erode;
      o.min_cut_solver = min_cut_solver(a->solver);
      // The start's own errors (no start, a model for other images) name the image or its list line.
      const MaskResult r = at(j.where.empty() ? j.image : j.where, [&] { return mask_image(*dev, img, start, o); });
      const std::string& out = outputs[k].first;  // named apart: clang 14 lambdas cannot capture a structured binding
      const std::string& overlay_path = outputs[k].second;
      timed_io([&] {
        io::write_png_grey(out, img.width, img.height, r.mask);
        if (!overlay_path.empty()) write_png(overlay_path, overlay(img, r.mask));
      });
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
      nlohmann::json e = {{"image", j.image},
                          {"mask", out},
                          {"width", img.width},
                          {"height", img.height},
                          {"pixels", uint64_t{img.width} * img.height},
                          {"foreground_fraction", r.foreground},
                          {"iterations", r.iterations},
                          {"seconds", seconds},
                          {"cut_value", r.cut_value}};
      if (!overlay_path.empty()) e["overlay"] = overlay_path;
      report.push_back(e);
      if (!a->json && !bar)
        std::printf("%s -> %s: %ux%u, %.1f %% foreground, %u iterations, %.2f s\n", j.image.c_str(), out.c_str(),
                    img.width, img.height, 100 * r.foreground, r.iterations, seconds);
      if (progress) progress("mask", double(k + 1) / double(jobs.size()));
    }
    if (bar) std::fprintf(stderr, "\n");
    nlohmann::json out{{"images", report}};
    if (g.profile) {
      const Parallelism p = meter.stop(io_seconds);
      if (a->json) out["parallelism"] = parallelism_json(p);
      else print_parallelism("mask apply", p);
    }
    if (a->json) std::cout << out.dump(2) << "\n";
    else if (bar)
      for (const auto& e : report)
        std::printf("%s -> %s: %.1f %% foreground, %d iterations, %.2f s\n", e["image"].get<std::string>().c_str(),
                    e["mask"].get<std::string>().c_str(), 100 * e["foreground_fraction"].get<double>(),
                    e["iterations"].get<int>(), e["seconds"].get<double>());
  });
}

void add_mask_train(CLI::App& mask) {
  struct Args {
    std::string images, masks, output;
    bool json = false, no_clobber = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = mask.add_subcommand(
      "train",
      "Build a histogram classifier from hand-made masks: 32 x 32 hue x saturation bins for colour images, 32\n"
      "value bins for one-channel range or reflectance maps; each bin holds fg / (fg + bg) of the training\n"
      "pixels (mask 255 foreground, 0 background, other values skipped). Images and masks pair by basename.\n"
      "Example:\n"
      "  megavox mask train --images train/photos --masks train/masks -o statue.mvm");
  cmd->add_option("--images", a->images, "Folder of images")->required();
  cmd->add_option("--masks", a->masks, "Folder of masks (8-bit grey, same basenames and sizes)")->required();
  cmd->add_option("-o,--output", a->output, "The model file (.mvm)")->required();
  cmd->add_flag("--json", a->json, "Print what was learnt as JSON");
  add_no_clobber_flag(*cmd, a->no_clobber);
  cmd->callback([a] {
    auto files = [](const std::string& dir) {
      std::map<std::string, std::string> by_stem;
      std::error_code ec;
      for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file()) by_stem[e.path().stem().string()] = e.path().string();
      if (ec) throw Error("cannot list the folder '" + dir + "': " + ec.message());
      return by_stem;
    };
    const auto images = files(a->images), masks = files(a->masks);
    std::vector<std::string> inputs;
    for (const auto* listed : {&images, &masks})
      for (const auto& [stem, path] : *listed) inputs.push_back(path);
    const std::string output = io::resolve_output({a->output, io::OutputKind::kFile, "mvm", inputs, 0, a->no_clobber});
    std::optional<MaskModel> model;
    nlohmann::json used = nlohmann::json::array();
    for (const auto& [stem, path] : images) {
      auto m = masks.find(stem);
      if (m == masks.end()) continue;
      const RasterImage img = io::read_image(path);
      const RasterImage mk = io::read_image(m->second);
      if (mk.channels != 1 || mk.max_value != 255)
        throw Error("mask '" + m->second + "': an 8-bit one-channel image is expected");
      if (!model) model = MaskModel::empty(img.channels);
      model->train(img, mk.samples, mk.width, mk.height);
      used.push_back({{"image", path}, {"mask", m->second}});
    }
    if (!model) throw Error("mask train: no image in '" + a->images + "' has a mask of its basename in '" + a->masks + "'");
    uint64_t fg = 0, bg = 0;
    for (uint32_t b = 0; b < model->bins(); ++b) fg += model->fg[b], bg += model->bg[b];
    if (fg == 0 || bg == 0) throw Error("mask train: the masks hold no " + std::string(fg == 0 ? "foreground (255)" : "background (0)") + " pixel");
    io::write_mvm(output, *model);
    if (a->json)
      std::cout << nlohmann::json{{"model", a->output}, {"channels", model->channels}, {"bins", model->bins()},
                                  {"foreground_pixels", fg}, {"background_pixels", bg}, {"pairs", used}}
                       .dump(2)
                << "\n";
    else
      std::printf("%s: %zu image/mask pairs, %u-channel model, %llu foreground and %llu background pixels\n",
                  a->output.c_str(), used.size(), model->channels, (unsigned long long)fg, (unsigned long long)bg);
  });
}

}  // namespace

void add_mask_command(CLI::App& app, const GlobalOptions& g) {
  auto* mask = app.add_subcommand("mask", "Masks of photographs and range maps: GrabCut on the device, histogram models");
  mask->require_subcommand(1);
  add_mask_train(*mask);
  add_mask_apply(*mask, g);
}

}  // namespace mv::cli

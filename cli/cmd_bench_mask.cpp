// `megavox bench mask`: min-cuts per second against Boost's BK, and GrabCut's error and time per image.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "baselines.h"
#include "mask_bench.h"
#include "cli_common.h"

namespace mv::cli {

void add_bench_mask_command(CLI::App& bench, const GlobalOptions& g) {
  struct Args {
    std::string data = "../shared/data/grabcut";
    uint32_t cut_images = 3, images = 0, iterations = 5;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "mask",
      "Min-cuts on the device against Boost.Graph's boykov_kolmogorov_max_flow (its max-flow call alone) on\n"
      "GrabCut's first-iteration graphs of the GrabCut database images, at their size and upscaled 2x (about\n"
      "1 MP), 4- and 8-connected, checking every cut is BK's; then GrabCut from the database boxes (--no-post\n"
      "error, post-processed error, seconds per image) beside OpenCV's cv::grabCut from the same boxes and\n"
      "iterations (its error and its call's seconds), where OpenCV is built in (scripts/setup.sh --bench).\n"
      "Example: megavox bench mask --data ../shared/data/grabcut --cut-images 3 --json");
  cmd->add_option("--data", a->data, "The GrabCut database folder (images/*.ppm, masks/*.pgm)");
  cmd->add_option("--cut-images", a->cut_images, "Images whose graphs are cut (first by name; default 3)");
  cmd->add_option("--images", a->images, "Images masked by GrabCut (default 0 = all)");
  cmd->add_option("--iterations", a->iterations, "GrabCut iterations (default 5)");
  cmd->add_flag("--json", a->json, "One JSON object");
  cmd->callback([a, &g] {
    auto dev = open_device(g);
    const auto cuts = bench::bench_cuts(*dev, a->data, a->cut_images);
    double mv_1mp8 = 0, bk_1mp8 = 0;
    nlohmann::json jc = nlohmann::json::array();
    if (!a->json) std::printf("%-8s %11s %4s %12s %12s %8s %s\n", "image", "size", "conn", "megavox/s", "BK/s", "ratio", "same cut");
    bool all_same = true;
    for (const auto& r : cuts) {
      if (r.width * uint64_t{r.height} > 600000 && r.connectivity == 8) mv_1mp8 += r.megavox_seconds, bk_1mp8 += r.bk_seconds;
      all_same &= r.same_cut;
      jc.push_back({{"image", r.image}, {"width", r.width}, {"height", r.height}, {"connectivity", r.connectivity},
                    {"megavox_cuts_per_second", 1 / r.megavox_seconds}, {"bk_cuts_per_second", 1 / r.bk_seconds},
                    {"value", r.value}, {"same_cut_as_bk", r.same_cut}});
      if (!a->json)
        std::printf("%-8s %5ux%-5u %4u %12.3f %12.3f %8.2f %s\n", r.image.c_str(), r.width, r.height, r.connectivity,
                    1 / r.megavox_seconds, 1 / r.bk_seconds, r.bk_seconds / r.megavox_seconds, r.same_cut ? "yes" : "NO");
    }
    const double speedup = mv_1mp8 > 0 ? bk_1mp8 / mv_1mp8 : 0;
    if (g.profile) dev->take_timings();  // the totals below are GrabCut's (masks and post-processing), not the cuts'
    const auto gc = bench::bench_grabcut(*dev, a->data, a->images, a->iterations);
    if (g.profile) print_kernel_totals(*dev);
    double err = 0, post = 0, secs = 0, cv_err = 0, cv_secs = 0, mv_secs_cv = 0;  // mv_secs_cv: where OpenCV ran
    uint64_t px = 0, cv_px = 0;
    size_t cv_n = 0;
    nlohmann::json jg = nlohmann::json::array();
    if (!a->json)
      std::printf("\n%-14s %9s %5s %10s %10s %8s %10s %8s\n", "image", "size", "iters", "error %", "post %", "s",
                  "opencv %", "opencv s");
    for (const auto& r : gc) {
      err += r.error, post += r.post_error, secs += r.seconds, px += uint64_t{r.width} * r.height;
      nlohmann::json j{{"image", r.image}, {"error", r.error}, {"post_error", r.post_error}, {"seconds", r.seconds},
                       {"iterations", r.iterations}};
      if (r.opencv) {
        cv_err += r.opencv_error, cv_secs += r.opencv_seconds, ++cv_n;
        mv_secs_cv += r.seconds, cv_px += uint64_t{r.width} * r.height;
        j["opencv_error"] = r.opencv_error;
        j["opencv_seconds"] = r.opencv_seconds;
      }
      jg.push_back(j);
      if (a->json) continue;
      std::printf("%-14s %4ux%-4u %5u %10.2f %10.2f %8.2f", r.image.c_str(), r.width, r.height, r.iterations,
                  100 * r.error, 100 * r.post_error, r.seconds);
      if (r.opencv)
        std::printf(" %10.2f %8.2f\n", 100 * r.opencv_error, r.opencv_seconds);
      else
        std::printf(" %10s %8s\n", "-", "-");
    }
    const double n = gc.empty() ? 1 : double(gc.size());
    const auto opencv = baseline::opencv();
    if (a->json) {
      nlohmann::json out{{"device", dev->info().name},
                                  {"cuts", jc},
                                  {"speedup_vs_bk", mv_1mp8 > 0 ? nlohmann::json(speedup) : nlohmann::json()},
                                  {"all_cuts_equal_bk", all_same},
                                  {"grabcut", jg},
                                  {"grabcut_mean_error", err / n},
                                  {"grabcut_mean_post_error", post / n},
                                  {"grabcut_seconds_per_image", secs / n},
                                  {"grabcut_mpx_per_second", secs > 0 ? px * 1e-6 / secs : 0.0}};
      if (cv_n) {
        out["opencv_mean_error"] = cv_err / double(cv_n);
        out["opencv_seconds_per_image"] = cv_secs / double(cv_n);
        out["opencv_mpx_per_second"] = cv_px * 1e-6 / cv_secs;
        out["time_ratio_to_opencv"] = mv_secs_cv / cv_secs;
      }
      out["missing_baselines"] = nlohmann::json::array();
      if (!opencv.built_in) out["missing_baselines"].push_back(baseline::missing_note(opencv));
      std::cout << out.dump(2) << "\n";
      return;
    }
    if (mv_1mp8 > 0)
      std::printf("speedup_vs_bk (~1 MP, 8-connected, total time): %.2f\n", speedup);
    else  // the figure is defined over those cuts only
      std::printf("speedup_vs_bk: not measured (no ~1 MP 8-connected cut among --cut-images %u)\n", a->cut_images);
    std::printf("GrabCut on %zu images from boxes, %u iterations: mean error %.2f %% (--no-post), %.2f %% post-processed; "
                "%.2f s per image, %.3f Mpx/s\n",
                gc.size(), a->iterations, 100 * err / n, 100 * post / n, secs / n, secs > 0 ? px * 1e-6 / secs : 0.0);
    if (cv_n)
      std::printf("OpenCV cv::grabCut, same boxes and iterations: mean error %.2f %%; %.2f s per image, %.3f Mpx/s "
                  "(megavox --no-post / OpenCV time: %.2f)\n",
                  100 * cv_err / double(cv_n), cv_secs / double(cv_n), cv_px * 1e-6 / cv_secs, mv_secs_cv / cv_secs);
    else
      std::printf("%s\n", baseline::missing_note(opencv).c_str());
  });
}

}  // namespace mv::cli

// `megavox points convert IN -o OUT`: LAS or LAZ rewritten as plain LAS (io/las_convert.h), every attribute and
// record kept, the points in file order: the plain way to decompress LAZ. Any cloud (LAS, LAZ, PLY) to PLY, and
// PLY to LAS, through the point readers (io/point_file_writers.h).
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_common.h"
#include "io/file_ops.h"
#include "io/las_convert.h"
#include "io/output_path.h"
#include "io/point_file_writers.h"
#include "io/point_source.h"
#include "megavox/error.h"

namespace mv::cli {

namespace {

struct ConvertArgs {
  std::string input, output, bounds;
  unsigned threads = 0;
  bool json = false, quiet = false, no_clobber = false;
};

}  // namespace

void add_points_convert(CLI::App& points) {
  auto a = std::make_shared<ConvertArgs>();
  auto* cmd = points.add_subcommand(
      "convert",
      "Rewrite a point cloud in file order, keeping every attribute the output holds:\n"
      "  LAS or LAZ (COPC included) -> .las: every record and attribute byte for byte, decompressed (the way to\n"
      "    decompress LAZ); the point format, scale, offset and records kept;\n"
      "  LAS, LAZ or PLY -> .ply: binary, world x y z as double, colour, intensity, normals and every LAS field by\n"
      "    name (classification, gps_time, ...);\n"
      "  PLY -> .las: LAS 1.4 format 6 (7 with colour) on the grid the PLY reader chose, normals as extra bytes.\n"
      "Example: megavox points convert scan.laz -o scan.las");
  cmd->add_option("input", a->input, "A .las, .laz or .ply file")->required();
  cmd->add_option("-o,--output", a->output, "The .las or .ply file to write (written whole or not at all)")->required();
  cmd->add_option("--bounds", a->bounds,
                  "Only the points in this box, MINX,MINY,MINZ,MAXX,MAXY,MAXZ in the file's world units (both ends "
                  "kept); a COPC file decodes only the chunks whose octree node meets it");
  cmd->add_option("--threads", a->threads, "LAZ chunks decoded at once (default: one per hardware thread)");
  cmd->add_flag("--no-clobber", a->no_clobber, "Refuse to replace an existing output");
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the summary");
  cmd->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  cmd->callback([a] {
    std::optional<std::array<double, 6>> bounds;
    if (!a->bounds.empty()) bounds = parse_bounds(a->bounds);
    const std::string kind = io::format_of_extension(a->output);
    const std::string output = io::resolve_output({a->output, io::OutputKind::kFile, kind, {a->input}, 0, a->no_clobber});
    if (kind != "las" && kind != "ply")
      throw Error(a->output + ": points convert writes LAS or PLY: name the output .las or .ply");
    const bool las_in = io::first_bytes(a->input, 4) == "LASF";
    if (bounds && !(las_in && kind == "las"))
      throw Error("--bounds keeps the points of a LAS or LAZ file in a box, written as .las");
    const bool tty = !a->quiet && !a->json && isatty(STDERR_FILENO);
    auto progress = [&](uint64_t done) {
      if (tty) std::fprintf(stderr, "\r%llu points", (unsigned long long)done);
    };
    io::LasConvertReport r;
    if (las_in && kind == "las") {
      r = io::write_plain_las(a->input, output, a->threads, progress, bounds);
    } else {
      io::PointReadOptions o;
      o.threads = a->threads;
      auto source = io::open_points(a->input, o);
      const auto start = std::chrono::steady_clock::now();
      r.points_written = kind == "ply" ? io::write_ply_points(*source, output, progress)
                                       : io::write_las_points(*source, output, progress);
      r.decode_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      r.input_format = source->info().format;
      r.points = r.points_written;
      r.bytes_written = std::filesystem::file_size(output);
    }
    if (tty) std::fprintf(stderr, "\n");
    if (a->quiet) return;
    if (a->json) {
      nlohmann::json j = {{"input", a->input},
                          {"output", a->output},
                          {"input_format", r.input_format},
                          {"points", r.points},
                          {"points_written", r.points_written},
                          {"chunks", r.chunks},
                          {"chunks_read", r.chunks_read},
                          {"record_length", r.record_length},
                          {"bytes_written", r.bytes_written},
                          {"decode_seconds", r.decode_seconds},
                          {"points_per_second", r.decode_seconds > 0 ? r.points / r.decode_seconds : 0.0}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    if (r.record_length)
      std::printf("%s (%s) -> %s: %llu points of %u bytes, %.3f s to decode (%.1f M points/s)\n", a->input.c_str(),
                  r.input_format.c_str(), a->output.c_str(), (unsigned long long)r.points_written, r.record_length,
                  r.decode_seconds, r.decode_seconds > 0 ? r.points / r.decode_seconds / 1e6 : 0.0);
    else
      std::printf("%s (%s) -> %s: %llu points, %llu bytes, %.3f s\n", a->input.c_str(), r.input_format.c_str(),
                  a->output.c_str(), (unsigned long long)r.points_written, (unsigned long long)r.bytes_written,
                  r.decode_seconds);
    if (bounds)
      std::printf("  in the bounds: %llu of the %llu points read; %llu of %llu chunks decoded\n",
                  (unsigned long long)r.points_written, (unsigned long long)r.points, (unsigned long long)r.chunks_read,
                  (unsigned long long)r.chunks);
  });
}

}  // namespace mv::cli

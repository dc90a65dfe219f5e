// `megavox points convert IN -o OUT`: LAS or LAZ rewritten as plain LAS (io/las_convert.h), every attribute and
// record kept, the points in file order: the plain way to decompress LAZ.
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>

#include "cli_common.h"
#include "io/file_ops.h"
#include "io/las_convert.h"
#include "io/output_path.h"
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
      "convert", "Rewrite a LAS or LAZ file (COPC included) as plain LAS: every point in file order, every "
                 "attribute and record kept (the way to decompress LAZ)");
  cmd->add_option("input", a->input, "A .las or .laz file")->required();
  cmd->add_option("-o,--output", a->output, "The .las file to write (written whole or not at all)")->required();
  cmd->add_option("--bounds", a->bounds,
                  "Only the points in this box, MINX,MINY,MINZ,MAXX,MAXY,MAXZ in the file's world units (both ends "
                  "kept); a COPC file decodes only the chunks whose octree node meets it");
  cmd->add_option("--threads", a->threads, "LAZ chunks decoded at once (default: one per hardware thread)");
  cmd->add_flag("--no-clobber", a->no_clobber, "Refuse to replace an existing output");
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the summary");
  cmd->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  cmd->callback([a] {
    if (io::first_bytes(a->input, 4) != "LASF")
      throw Error(a->input + ": not a LAS or LAZ file (it does not start with 'LASF'); points convert reads LAS and LAZ");
    std::optional<std::array<double, 6>> bounds;
    if (!a->bounds.empty()) bounds = parse_bounds(a->bounds);
    const std::string output = io::resolve_output({a->output, io::OutputKind::kFile, "las", {a->input}, 0, a->no_clobber});
    if (io::format_of_extension(a->output) != "las")
      throw Error(a->output + ": points convert writes plain LAS: name the output .las");
    const bool tty = !a->quiet && !a->json && isatty(STDERR_FILENO);
    const io::LasConvertReport r = io::write_plain_las(a->input, output, a->threads, [&](uint64_t done) {
      if (tty) std::fprintf(stderr, "\r%llu points", (unsigned long long)done);
    }, bounds);
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
    std::printf("%s (%s) -> %s: %llu points of %u bytes, %.3f s to decode (%.1f M points/s)\n", a->input.c_str(),
                r.input_format.c_str(), a->output.c_str(), (unsigned long long)r.points_written, r.record_length,
                r.decode_seconds, r.decode_seconds > 0 ? r.points / r.decode_seconds / 1e6 : 0.0);
    if (bounds)
      std::printf("  in the bounds: %llu of the %llu points read; %llu of %llu chunks decoded\n",
                  (unsigned long long)r.points_written, (unsigned long long)r.points, (unsigned long long)r.chunks_read,
                  (unsigned long long)r.chunks);
  });
}

}  // namespace mv::cli

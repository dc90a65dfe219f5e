// `megavox export` and `megavox import`: files other voxel tools read and write.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "megavox/interop.h"
#include "option_words.h"

namespace mv::cli {

void add_export_command(CLI::App& app, const GlobalOptions& g) {
  auto o = std::make_shared<ExportOptions>();
  auto format = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand(
      "export",
      "Write a .mvx for other tools: SymVox-family DAG files (the SSVDAG authors' viewer; voxcom reads the 32-bit\n"
      "ones; geometry only), the voxels as an OpenVDB mask grid / NanoVDB grid named 'voxels' (with a Vec3s grid\n"
      "'colour' beside it when the file has colours), or as a PLY of voxel centres with their colours. Examples:\n"
      "  megavox export bunny.mvx --format symvox-ssvdag -o bunny.ssvdag\n"
      "  megavox export bunny.mvx --format vdb -o bunny.vdb\n"
      "  megavox export lion.mvx --format ply -o lion_voxels.ply");
  cmd->add_option("file", o->input, "The .mvx file")->required();
  cmd->add_option("-o,--output", o->output, "The file to write (named only once complete)")->required();
  add_no_clobber_flag(*cmd, o->no_clobber);
  cmd->add_option("--format", *format,
                  "symvox-svdag (32-bit SVDAG), symvox-ussvdag (32-bit, per-child mirror bits), symvox-ssvdag\n"
                  "(SymVox's compact 16-bit SSVDAG), vdb (OpenVDB MaskGrid, + Vec3s 'colour'), nvdb (NanoVDB) or ply (one vertex per\n"
                  "voxel: its centre, and uchar red, green, blue when the file has colours)")
      ->required()
      ->check(CLI::IsMember({"symvox-svdag", "symvox-ussvdag", "symvox-ssvdag", "vdb", "nvdb", "ply"}));
  cmd->add_flag("--json", *json, "Print one JSON object");
  cmd->callback([&g, o, format, json] {
    o->format = parse_export_format(*format);
    check_output(*o);  // before the device opens
    auto dev = open_device(g);
    ExportReport r = export_mvx(*dev, *o);
    if (*json) {
      std::cout << nlohmann::json{{"input", r.input}, {"output", r.output}, {"format", r.format},
                                  {"voxels", r.voxels}, {"bytes", r.bytes}, {"rebuilt", r.rebuilt},
                                  {"colours_dropped", r.colours_dropped}}
                       .dump(2)
                << "\n";
      return;
    }
    std::printf("%s -> %s (%s%s): %llu voxels, %llu bytes\n", r.input.c_str(), r.output.c_str(), r.format.c_str(),
                r.rebuilt ? ", re-encoded from the voxels" : "", (unsigned long long)r.voxels,
                (unsigned long long)r.bytes);
    if (r.colours_dropped)
      std::fprintf(stderr, "megavox: %s: its voxel colours are not exported: %s files hold geometry only (export "
                           "--format ply or vdb keeps them)\n", r.input.c_str(), r.format.c_str());
  });
}

void add_import_command(CLI::App& app, const GlobalOptions& g) {
  auto o = std::make_shared<ImportOptions>();
  auto convention = std::make_shared<std::string>("auto"), format = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand(
      "import",
      "Read a SymVox-family DAG file (.svdag, .ussvdag: 32-bit; .ssvdag: SymVox's 16-bit, or voxcom's 32-bit\n"
      "under that name) into a .mvx. The layout is told from the content, not the name, and fully validated.\n"
      "Example: megavox import scene.ussvdag -o scene.mvx");
  cmd->add_option("file", o->input, "The SymVox-family file")->required();
  cmd->add_option("-o,--output", o->output, "The .mvx to write (named only once complete)")->required();
  add_no_clobber_flag(*cmd, o->no_clobber);
  cmd->add_option("--convention", *convention,
                  "Who wrote it: symvox (child 4x+2y+z, cube centred on the bbox), voxcom (Morton child order, cube at\n"
                  "the bbox's min corner, voxel units) or auto (voxcom when the bbox starts at 0 and the root side is\n"
                  "the resolution)")
      ->check(CLI::IsMember({"auto", "symvox", "voxcom"}))
      ->capture_default_str();
  cmd->add_option("--format", *format, "Encoding of the .mvx: svdag, ussvdag or ssvdag (default: the file's layout)")
      ->check(CLI::IsMember({"svdag", "ussvdag", "ssvdag"}));
  cmd->add_flag("--json", *json, "Print one JSON object");
  cmd->callback([&g, o, convention, format, json] {
    o->convention = parse_symvox_convention(*convention);
    if (!format->empty()) o->encoding = parse_encoding(*format);
    check_output(*o);  // before the device opens
    auto dev = open_device(g);
    ImportReport r = import_symvox(*dev, *o);
    if (*json) {
      std::cout << nlohmann::json{{"input", r.input},       {"output", r.output},       {"layout", r.layout},
                                  {"convention", r.convention}, {"format", r.format},   {"levels", r.levels},
                                  {"resolution", 1u << r.levels}, {"voxels", r.voxels}, {"file_nodes", r.file_nodes},
                                  {"nodes_total", r.nodes_total}, {"bytes", r.bytes}}
                       .dump(2)
                << "\n";
      return;
    }
    std::printf("%s (%s layout, %s convention, %u^3) -> %s (%s): %llu voxels, %llu DAG nodes, %llu bytes\n",
                r.input.c_str(), r.layout.c_str(), r.convention.c_str(), 1u << r.levels, r.output.c_str(),
                r.format.c_str(), (unsigned long long)r.voxels, (unsigned long long)r.nodes_total,
                (unsigned long long)r.bytes);
  });
}

}  // namespace mv::cli

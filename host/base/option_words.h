// The words front ends take for the library's enums (the CLI's flags, the C API's strings): below them the
// library passes enums, and each word is parsed once, here, at the edge. A parse throws
// CodedError(invalid_argument) naming the choices and the setting; a name is what a report prints.
#pragma once
#include <string>
#include <string_view>

#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/interop.h"
#include "megavox/point_build.h"
#include "megavox/voxelize.h"

namespace mv {

// "svo", "svdag", "ussvdag", "ssvdag" (encoding_name in megavox/mvx.h is the other way).
inline Encoding parse_encoding(std::string_view word) {
  if (word == "svo") return Encoding::svo;
  if (word == "svdag") return Encoding::svdag;
  if (word == "ussvdag") return Encoding::ussvdag;
  if (word == "ssvdag") return Encoding::ssvdag;
  throw CodedError(ErrorCode::invalid_argument, "encoding '" + std::string(word) + "': choose svo, svdag, ussvdag or ssvdag",
                   setting_encoding);
}

// "conservative" (26-separating) or "thin" (6-separating).
inline Voxelizer::Rule parse_voxelize_rule(std::string_view word) {
  if (word == "conservative") return Voxelizer::Rule::kConservative;
  if (word == "thin") return Voxelizer::Rule::kThin;
  throw CodedError(ErrorCode::invalid_argument,
                   "voxelization rule '" + std::string(word) + "': choose conservative or thin", setting_voxelize);
}
inline const char* voxelize_rule_name(Voxelizer::Rule rule) {
  return rule == Voxelizer::Rule::kThin ? "thin" : "conservative";
}

// "mvx" or "3dtiles".
inline PointOutput parse_point_output(std::string_view word) {
  if (word == "mvx") return PointOutput::mvx;
  if (word == "3dtiles") return PointOutput::tiles3d;
  throw CodedError(ErrorCode::invalid_argument, "point output format '" + std::string(word) + "': choose mvx or 3dtiles",
                   setting_encoding);
}
inline const char* point_output_name(PointOutput o) { return o == PointOutput::tiles3d ? "3dtiles" : "mvx"; }

// "symvox-svdag", "symvox-ussvdag", "symvox-ssvdag", "vdb", "nvdb" or "ply" (also output_path.h's format names).
inline ExportFormat parse_export_format(std::string_view word) {
  if (word == "symvox-svdag") return ExportFormat::symvox_svdag;
  if (word == "symvox-ussvdag") return ExportFormat::symvox_ussvdag;
  if (word == "symvox-ssvdag") return ExportFormat::symvox_ssvdag;
  if (word == "vdb") return ExportFormat::vdb;
  if (word == "nvdb") return ExportFormat::nvdb;
  if (word == "ply") return ExportFormat::ply;
  throw CodedError(ErrorCode::invalid_argument,
                   "export format '" + std::string(word) +
                       "': choose symvox-svdag, symvox-ussvdag, symvox-ssvdag, vdb, nvdb or ply",
                   setting_encoding);
}
inline const char* export_format_name(ExportFormat f) {
  switch (f) {
    case ExportFormat::symvox_svdag: return "symvox-svdag";
    case ExportFormat::symvox_ussvdag: return "symvox-ussvdag";
    case ExportFormat::symvox_ssvdag: return "symvox-ssvdag";
    case ExportFormat::vdb: return "vdb";
    case ExportFormat::nvdb: return "nvdb";
    case ExportFormat::ply: return "ply";
  }
  return "?";
}

// "auto", "symvox" or "voxcom".
inline SymvoxConvention parse_symvox_convention(std::string_view word) {
  if (word == "auto") return SymvoxConvention::automatic;
  if (word == "symvox") return SymvoxConvention::symvox;
  if (word == "voxcom") return SymvoxConvention::voxcom;
  throw CodedError(ErrorCode::invalid_argument,
                   "convention '" + std::string(word) + "': choose auto, symvox or voxcom");
}
inline const char* symvox_convention_name(SymvoxConvention c) {
  return c == SymvoxConvention::voxcom ? "voxcom" : c == SymvoxConvention::symvox ? "symvox" : "auto";
}

}  // namespace mv

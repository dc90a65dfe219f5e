// `megavox export` and `megavox import`: .mvx <-> SymVox-family files, .mvx -> OpenVDB / NanoVDB.
#include "megavox/interop.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/morton.h"
#include "voxel/build_steps.h"
#include "io/output_path.h"
#include "io/symvox_file.h"
#include "io/vdb_writer.h"
#include "io/voxel_ply.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "option_words.h"

namespace mv {

namespace {

std::optional<Encoding> symvox_encoding(ExportFormat format) {
  switch (format) {
    case ExportFormat::symvox_svdag: return Encoding::svdag;
    case ExportFormat::symvox_ussvdag: return Encoding::ussvdag;
    case ExportFormat::symvox_ssvdag: return Encoding::ssvdag;
    default: return std::nullopt;
  }
}

// The file's contents in `format`: as stored when it already is, else decoded and rebuilt.
MvxFile in_format(Device& dev, MvxFile in, Encoding encoding, bool& rebuilt) {
  if (in.dag.encoding == encoding) return in;
  rebuilt = true;
  Dag dag = build_dag_for_format(dev, decode_encoded(in.dag), in.dag.levels, encoding);
  return mvx_for_dag(dag, encoding, in.grid, in.bounds);
}

// SymVox centres the root cube on the bbox: write the model's bounds grown to be symmetric about the
// cube's centre, so any placement (min corner, explicit cube) lands where megavox put it.
void symvox_box(const MvxFile& in, io::SymvoxFile& out) {
  const double side = in.grid.voxel_size * in.grid.resolution;
  for (int a = 0; a < 3; ++a) {
    const double c = in.grid.origin[a] + 0.5 * side;
    double h = std::max(c - in.bounds.lo[a], in.bounds.hi[a] - c);
    if (!(h >= 0) || h > 0.5 * side) h = 0.5 * side;
    out.bbox_min[a] = static_cast<float>(c - h);
    out.bbox_max[a] = static_cast<float>(c + h);
  }
  out.root_side = static_cast<float>(side);
}

// The voxels' own colours out of the depth-first array: leaves in pre-order come in Morton order, each after
// the inner nodes it is the first voxel of (the levels where its code first differs from the voxel before).
std::vector<uint8_t> voxel_colours(const std::vector<uint64_t>& keys, const std::vector<uint8_t>& colours,
                                   uint32_t levels) {
  if (colours.empty()) return {};
  std::vector<uint8_t> out(keys.size() * 3);
  uint64_t index = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    uint32_t fresh = levels;  // the first voxel opens every level, the root included
    if (i > 0) {
      fresh = 0;
      for (uint32_t l = 1; l < levels; ++l) fresh += (keys[i] >> (3 * l)) != (keys[i - 1] >> (3 * l));
    }
    index += fresh;
    if (3 * index + 3 > colours.size()) throw Error("export: the colours end before the voxels do");
    std::copy(colours.begin() + 3 * index, colours.begin() + 3 * index + 3, out.begin() + 3 * i);
    ++index;
  }
  return out;
}

}  // namespace

std::string check_output(const ExportOptions& o) {
  return io::resolve_output(
      {o.output, io::OutputKind::kFile, export_format_name(o.format), {o.input}, 0, o.no_clobber});
}

std::string check_output(const ImportOptions& o) {
  return io::resolve_output({o.output, io::OutputKind::kFile, "mvx", {o.input}, 0, o.no_clobber});
}

ExportReport export_mvx(Device& dev, const ExportOptions& o) {
  ExportReport r{o.input, o.output, export_format_name(o.format)};
  const std::optional<Encoding> encoding = symvox_encoding(o.format);
  const std::string output = check_output(o);
  MvxFile in = read_mvx(o.input);
  r.voxels = in.voxels;
  if (o.format == ExportFormat::ply) {
    const std::vector<uint64_t> keys = decode_encoded(in.dag);
    io::write_voxel_ply(output, keys, in.grid, voxel_colours(keys, in.colours, in.dag.levels));
  } else if (!encoding) {
    const std::vector<uint64_t> keys = decode_encoded(in.dag);
    io::write_voxel_grid(output, keys, in.grid, o.format == ExportFormat::nvdb,
                         voxel_colours(keys, in.colours, in.dag.levels));
  } else {
    r.colours_dropped = !in.colours.empty();
    MvxFile dag = in_format(dev, std::move(in), *encoding, r.rebuilt);
    io::SymvoxFile out;
    out.levels = dag.dag.levels;
    symvox_box(dag, out);
    // SymVox counts every node of levels 1..L, the root only in its .svdag.
    uint64_t nodes = 0;
    for (size_t l = 1; l < dag.dag_nodes.size(); ++l) nodes += dag.dag_nodes[l];
    if (*encoding != Encoding::svdag) nodes -= 1;
    out.dag = std::move(dag.dag);
    out.nodes = static_cast<uint32_t>(std::min<uint64_t>(nodes, UINT32_MAX));
    io::write_symvox(output, out);
  }
  r.bytes = std::filesystem::file_size(output);
  return r;
}

ImportReport import_symvox(Device& dev, const ImportOptions& o) {
  const std::string output = check_output(o);
  io::SymvoxFile f = io::read_symvox(o.input);
  ImportReport r;
  r.input = o.input;
  r.output = o.output;
  r.layout = encoding_name(f.dag.encoding);
  r.levels = f.levels;
  r.file_nodes = f.nodes;
  const double resolution = std::ldexp(1.0, int(f.levels));
  const bool looks_voxcom = f.bbox_min[0] == 0 && f.bbox_min[1] == 0 && f.bbox_min[2] == 0 &&
                            std::abs(f.root_side - resolution) <= 1e-3 * resolution;
  const SymvoxConvention convention = o.convention != SymvoxConvention::automatic ? o.convention
                                      : looks_voxcom                               ? SymvoxConvention::voxcom
                                                                                   : SymvoxConvention::symvox;
  r.convention = symvox_convention_name(convention);
  const Encoding encoding = o.encoding.value_or(f.dag.encoding);
  if (encoding == Encoding::svo)
    throw CodedError(ErrorCode::invalid_argument, "encoding svo: choose svdag, ussvdag or ssvdag", setting_encoding);
  r.format = encoding_name(encoding);

  std::vector<uint64_t> keys = decode_encoded(f.dag);
  const bool voxcom = convention == SymvoxConvention::voxcom;
  if (voxcom) {  // its Morton child order reads as the model with x and z swapped: swap them back
    for (uint64_t& k : keys) k = mv_morton3_64(mv_morton3_64_axis(k, 2), mv_morton3_64_axis(k, 1), mv_morton3_64_axis(k, 0));
    std::sort(keys.begin(), keys.end());
  }
  GridTransform grid;
  grid.resolution = static_cast<uint32_t>(resolution);
  grid.voxel_size = double(f.root_side) / resolution;
  Bounds bounds;
  for (int a = 0; a < 3; ++a) {
    grid.origin[a] = voxcom ? f.bbox_min[a] : 0.5 * (double(f.bbox_min[a]) + f.bbox_max[a]) - 0.5 * f.root_side;
    bounds.lo[a] = f.bbox_min[a];
    bounds.hi[a] = f.bbox_max[a];
  }
  Dag dag = build_dag_for_format(dev, keys, f.levels, encoding);
  MvxFile out = mvx_for_dag(dag, encoding, grid, bounds);
  write_mvx(output, out);
  r.voxels = out.voxels;
  r.nodes_total = nodes_total(out);
  r.bytes = out.dag.bytes();
  return r;
}

}  // namespace mv

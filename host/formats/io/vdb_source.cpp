#include "io/vdb_source.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <ios>
#include <new>
#include <string>
#include <string_view>

#include "io/file_ops.h"
#include "io/vdb_grid_reader.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

uint64_t morton_key(uint64_t x, uint64_t y, uint64_t z) {
  uint64_t key = 0;
  for (int b = 0; b < 21; ++b) key |= (x >> b & 1) << (3 * b) | (y >> b & 1) << (3 * b + 1) | (z >> b & 1) << (3 * b + 2);
  return key;
}

}  // namespace

bool is_vdb(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // the mesh readers name what is wrong
  return first_bytes(path, 4) == std::string(" BDV", 4);
}

namespace {

// The fuzz build (fuzz/) stops at 2^15 selected voxels (8 tiles of 16^3): a few bytes of active tiles, or of
// compressed leaves, legitimately stand for millions of voxels (fuzz/known/vdb_tiles_63M_voxels.vdb: 10 KB,
// 63 M voxels; fuzz/corpus/fuzz_vdb/regression_leaves_many_voxels.vdb: 27 KB of leaves), which only makes fuzzing
// slow (at 2^20, mutants near the limit made one execution 50 ms of expanding and sorting) and, past the fuzz
// build's 64 MiB allocations, stops it. Elsewhere there is no limit but memory's (the host's memory budget).
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
constexpr uint64_t kMaxVoxels = uint64_t{1} << 15;
#else
constexpr uint64_t kMaxVoxels = UINT64_MAX;
#endif

// The coordinates of a grid's active values that `keep` selects, active tiles expanded. `keep` takes the
// value by reference: see set_byte.
template <class GridT, class Keep>
void collect(const GridT& grid, const Keep& keep, const std::string& path, std::vector<openvdb::Coord>& coords) {
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    if (!keep(*it)) continue;
    if (it.isVoxelValue()) {
      if (coords.size() == kMaxVoxels)
        throw Error(path + ": selects more than " + std::to_string(kMaxVoxels) + " voxels (the fuzz build's limit)");
      coords.push_back(it.getCoord());
    } else {  // an active tile: all of its voxels
      openvdb::CoordBBox box;
      it.getBoundingBox(box);
      if (box.volume() > (uint64_t{1} << 32)) throw Error(path + ": an active tile is too large to expand");
      if (box.volume() > kMaxVoxels - coords.size())
        throw Error(path + ": selects more than " + std::to_string(kMaxVoxels) + " voxels (the fuzz build's limit)");
      for (auto c = box.begin(); c; ++c) coords.push_back(*c);
    }
  }
}

// Whether a bool value from a file is set. OpenVDB reads tile values of bool and mask grids as raw bytes, so
// one may hold any byte (190 in tests/fuzz_regressions/): loading it as a bool is undefined, its byte is not.
bool set_byte(const bool& v) {
  unsigned char b;
  std::memcpy(&b, &v, 1);
  return b != 0;
}

// Text from the file (grid names and types, which OpenVDB's messages quote) as messages show it: a damaged
// length gave a 33 MB grid type (tests/fuzz_regressions/vdb_33MB_grid_type.vdb).
std::string clip(std::string_view text) {
  constexpr size_t kMax = 200;
  if (text.size() <= kMax) return std::string(text);
  return std::string(text.substr(0, kMax)) + "... (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace

VdbVoxels read_vdb(const std::string& path, const std::string& name, uint32_t resolution) {
  openvdb::initialize();
  VdbVoxels out;
  openvdb::GridBase::Ptr base;
  try {
    // (OpenVDB's delayed loading is not used: every voxel is read below anyway, and its delayed-load path trusts
    // the file's per-leaf table without bounds checks: tests/fuzz_regressions/vdb_delayed_load_mask.vdb.)
    std::string wanted = name;
    base = read_vdb_grid(path, wanted);
    if (!base && name.empty()) throw Error(path + ": the file holds no grids");
    if (!base) throw Error(path + ": no grid named '" + clip(name) + "'");
    out.grid_name = wanted;
  } catch (const Error&) {
    throw;
  } catch (const std::ios_base::failure&) {  // the stream's exceptions: see vdb_grid_reader.h
    throw Error(path + ": cannot read the OpenVDB file (the file ends before the data it declares: truncated or damaged)");
  } catch (const std::bad_alloc&) {
    // OpenVDB allocates the sizes a stream declares before reading them: a damaged size asks for gigabytes
    // (tests/fuzz_regressions/vdb_blosc_size_bad_alloc.vdb).
    throw Error(path + ": cannot read the OpenVDB file (it declares more data than memory holds: damaged?)");
  } catch (const std::exception& e) {  // openvdb::Exception, and the C++ library's exceptions OpenVDB lets through
    throw Error(path + ": cannot read the OpenVDB file (" + clip(e.what()) + ")");
  }
  std::vector<openvdb::Coord> coords;
  if (auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base)) {
    const bool level_set = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
    out.grid_class = level_set ? "level set" : "fog volume";
    const float band = static_cast<float>(0.5 * grid->voxelSize()[0]);
    collect(*grid, [&](const float& v) { return level_set ? std::abs(v) <= band : v > 0.0f; }, path, coords);
  } else if (auto mask = openvdb::gridPtrCast<openvdb::MaskGrid>(base)) {
    out.grid_class = "mask";
    collect(*mask, [](const bool&) { return true; }, path, coords);
  } else if (auto flags = openvdb::gridPtrCast<openvdb::BoolGrid>(base)) {
    out.grid_class = "mask";
    collect(*flags, [](const bool& v) { return set_byte(v); }, path, coords);
  } else {
    throw Error(path + ": grid '" + clip(out.grid_name) + "' holds " + clip(base->valueType()) +
                " values; megavox reads float grids (level sets, fog volumes) and mask / bool grids");
  }
  const double vs = base->voxelSize()[0];
  if (coords.empty()) throw Error(path + ": grid '" + clip(out.grid_name) + "' selects no voxels");
  openvdb::Coord lo = coords[0], hi = coords[0];
  for (const auto& c : coords) {
    lo.minComponent(c);
    hi.maxComponent(c);
  }
  uint64_t extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max<uint64_t>(extent, uint64_t(int64_t(hi[a]) - lo[a] + 1));
  // A megavox grid has at most 2^21 voxels per axis (64-bit Morton keys). The power of two is found in 64 bits:
  // voxels 2^31 apart made a 32-bit one wrap to 0 and loop forever.
  constexpr uint64_t kMaxSide = uint64_t{1} << 21;
  uint64_t n = 8;
  while (n < extent) n *= 2;
  if (resolution == 0) {
    if (n > kMaxSide)
      throw Error(path + ": grid '" + clip(out.grid_name) + "' spans " + std::to_string(extent) +
                  " voxels, more than the 2097152 per axis a megavox grid holds (a smaller resolution resamples it)");
    resolution = static_cast<uint32_t>(n);
  }
  // One VDB voxel = one voxel; a smaller --resolution resamples: the cube of `extent` VDB voxels is split into
  // `resolution` voxels per axis and a voxel is set when any selected VDB voxel's index maps into it,
  // i' = floor((i - min) * resolution / extent) (integer arithmetic, exact).
  const bool resample = resolution < extent;
  out.extent = static_cast<uint32_t>(extent);
  out.keys.reserve(coords.size());
  auto cell = [&](int64_t i) { return resample ? uint64_t(i) * resolution / extent : uint64_t(i); };
  for (const auto& c : coords)
    out.keys.push_back(morton_key(cell(int64_t{c[0]} - lo[0]), cell(int64_t{c[1]} - lo[1]),  // 64-bit: a span over
                                  cell(int64_t{c[2]} - lo[2])));                              // 2^31 (UBSan)
  std::sort(out.keys.begin(), out.keys.end());
  out.keys.erase(std::unique(out.keys.begin(), out.keys.end()), out.keys.end());
  for (int a = 0; a < 3; ++a) out.index_min[a] = lo[a];
  // VDB voxels are centred on their integer index: voxel lo covers [lo - 1/2, lo + 1/2) in index space.
  openvdb::Vec3d o = base->transform().indexToWorld(openvdb::Vec3d(lo[0] - 0.5, lo[1] - 0.5, lo[2] - 0.5));
  openvdb::Vec3d top = base->transform().indexToWorld(openvdb::Vec3d(hi[0] + 0.5, hi[1] + 0.5, hi[2] + 0.5));
  out.grid.origin[0] = o[0];
  out.grid.origin[1] = o[1];
  out.grid.origin[2] = o[2];
  out.grid.voxel_size = resample ? vs * double(extent) / resolution : vs;
  out.grid.resolution = resolution;
  out.bounds.extend(o[0], o[1], o[2]);
  out.bounds.extend(top[0], top[1], top[2]);
  return out;
}

}  // namespace mv::io

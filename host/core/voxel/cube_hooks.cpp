#include "voxel/cube_hooks.h"

#include <cmath>
#include <cstring>
#include <filesystem>

#include "common/morton.h"
#include "io/cube_parts.h"
#include "megavox/error.h"

namespace mv {

namespace {

void keep_cubes(const BuildOptions& o, CubeExchange& ex, uint64_t& cubes_resumed) {
  std::filesystem::create_directories(o.resume_dir);
  ex.load = [&o, &cubes_resumed](uint64_t c, std::vector<uint8_t>& payload) -> std::optional<Dag> {
    std::optional<std::vector<uint8_t>> bytes = io::read_cube_part(o.resume_dir, c, o.resume_fingerprint);
    if (!bytes) return std::nullopt;
    size_t used = 0;
    Dag part;
    try {
      part = io::unpack_dag(*bytes, &used);
    } catch (const Error&) {  // damaged past its checksum's reach: made again
      return std::nullopt;
    }
    payload.assign(bytes->begin() + static_cast<std::ptrdiff_t>(used), bytes->end());
    ++cubes_resumed;
    return part;
  };
  ex.keep = [&o](uint64_t c, const Dag& part, std::vector<uint8_t> payload) {
    std::vector<uint8_t> bytes = io::pack_dag(part);
    bytes.insert(bytes.end(), payload.begin(), payload.end());
    io::write_cube_part(o.resume_dir, c, o.resume_fingerprint, bytes);
  };
}

// A cube's colours as a payload: its keys (8 bytes each), then their colours (4 bytes each).
void carry_colours(CubeExchange& ex, CubeColours& cc) {
  auto bytes_from = [&cc](size_t from) {
    const size_t n = cc.keys.size() - from;
    std::vector<uint8_t> bytes(n * 12);
    std::memcpy(bytes.data(), cc.keys.data() + from, n * 8);
    std::memcpy(bytes.data() + n * 8, cc.rgb.data() + from, n * 4);
    return bytes;
  };
  ex.take_payload = [&cc, bytes_from] {
    std::vector<uint8_t> bytes = bytes_from(0);
    cc.keys.clear();
    cc.rgb.clear();
    return bytes;
  };
  ex.peek_payload = [&cc, bytes_from] { return bytes_from(cc.cube_at); };
  ex.put_payload = [&cc](std::vector<uint8_t>& bytes) {
    if (bytes.size() % 12) throw Error("a cube's colours from another rank or a kept cube are cut short");
    const size_t n = bytes.size() / 12, at = cc.keys.size();
    cc.keys.resize(at + n);
    cc.rgb.resize(at + n);
    std::memcpy(cc.keys.data() + at, bytes.data(), n * 8);
    std::memcpy(cc.rgb.data() + at, bytes.data() + n * 8, n * 4);
  };
}

}  // namespace

std::vector<uint64_t> cube_voxel_estimates(const TriangleBuckets& buckets, uint32_t per_axis) {
  std::vector<uint64_t> voxels(uint64_t{per_axis} * per_axis * per_axis);
  for (uint64_t c = 0; c < voxels.size(); ++c)
    voxels[c] = static_cast<uint64_t>(std::llround(buckets.voxel_estimate(
        mv_morton3_64_axis(c, 0), mv_morton3_64_axis(c, 1), mv_morton3_64_axis(c, 2))));
  return voxels;
}

std::optional<CubeExchange> cube_hooks(const BuildOptions& o, const TriangleBuckets& buckets, uint32_t per_axis,
                                       CubeColours* colours, uint64_t& cubes_resumed,
                                       const std::vector<uint64_t>* dealt) {
  std::optional<CubeExchange> ex;
  if (o.ranks) ex = o.ranks->exchange(dealt ? *dealt : cube_voxel_estimates(buckets, per_axis));
  if (!o.resume_dir.empty()) {
    if (!ex) ex.emplace();
    keep_cubes(o, *ex, cubes_resumed);
  }
  if (ex && colours) carry_colours(*ex, *colours);
  return ex;
}

}  // namespace mv

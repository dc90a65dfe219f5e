#include "reduction_bench.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <vector>

#include "io/mesh_source.h"
#include "megavox/dag.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/voxelize.h"

#include "plain_read.h"
#include "stopwatch.h"

namespace mv::bench {

namespace {

uint64_t nodes_above_masks(const Dag& d) {
  uint64_t n = 0;
  for (uint32_t l = 2; l <= d.levels; ++l) n += d.nodes(l);
  return n;
}

}  // namespace

ReductionBenchResult run_reduction_bench(Device& dev, const std::string& mesh, uint32_t resolution, int repeats) {
  ReductionBenchResult r;
  r.mesh = mesh;
  r.resolution = resolution;
  r.read_gb_per_s = plain_read(mesh).gb_per_s();
  auto reader = io::open_mesh(mesh);
  std::vector<uint32_t> idx, all;
  while (reader->next_triangles(idx, 1u << 20)) all.insert(all.end(), idx.begin(), idx.end());
  Bounds b;
  const auto& pos = reader->positions();
  for (uint32_t v : all) b.extend(pos[3 * size_t{v}], pos[3 * size_t{v} + 1], pos[3 * size_t{v} + 2]);
  if (b.empty()) throw Error(mesh + ": the mesh has no triangles");
  GridTransform grid = grid_for_bounds(b, resolution);
  std::vector<float> tris;
  triangles_to_grid(grid, pos, all.data(), all.size() / 3, tris);
  r.triangles = all.size() / 3;

  {  // warm-up: kernels are built on first use; keep that out of the timings
    Voxelizer warm(dev, resolution);
    warm.add(std::vector<float>(tris.begin(), tris.begin() + std::min<size_t>(tris.size(), 9 * 16)));
    std::vector<uint64_t> few = warm.take_keys();
    const uint32_t lv = static_cast<uint32_t>(std::lround(std::log2(double(resolution))));
    build_svdag(dev, few, lv);
    build_ssvdag(dev, few, lv);
  }
  auto t = Clock::now();
  Voxelizer vox(dev, resolution);
  vox.add(tris);
  std::vector<uint64_t> voxels = vox.take_keys();
  r.voxelize_seconds = since(t);
  r.voxels = voxels.size();

  const uint32_t levels = static_cast<uint32_t>(std::lround(std::log2(double(resolution))));
  // Alternate the two reductions, best of `repeats` each: timings on a shared machine drift by tens of
  // percent. Each back-to-back pair also gives a ratio; their median is the steadier figure under load.
  Dag plain, sym;
  r.svo_seconds = r.svdag_seconds = r.ssvdag_seconds = 1e30;
  std::vector<double> pair_ratios;
  for (int rep = 0; rep < std::max(repeats, 1); ++rep) {
    DagBuildTimes plain_t, sym_t;
    plain = build_svdag(dev, voxels, levels, &plain_t);
    sym = build_ssvdag(dev, voxels, levels, &sym_t);
    r.svo_seconds = std::min({r.svo_seconds, plain_t.svo_seconds, sym_t.svo_seconds});
    r.svdag_seconds = std::min(r.svdag_seconds, plain_t.reduce_seconds);
    r.ssvdag_seconds = std::min(r.ssvdag_seconds, sym_t.reduce_seconds);
    pair_ratios.push_back(sym_t.reduce_seconds / plain_t.reduce_seconds);
  }
  std::sort(pair_ratios.begin(), pair_ratios.end());
  r.time_ratio_median = pair_ratios[pair_ratios.size() / 2];
  r.svdag_nodes = nodes_above_masks(plain);
  r.ssvdag_nodes = nodes_above_masks(sym);
  r.svdag_bytes = encode_svdag(plain).words.size() * 4;
  r.ussvdag_bytes = encode_svdag(sym).words.size() * 4;
  r.ssvdag_bytes = encode_ssvdag(sym).bytes();
  r.svdag_voxels_per_s = double(r.voxels) / r.svdag_seconds;
  r.ssvdag_voxels_per_s = double(r.voxels) / r.ssvdag_seconds;
  r.time_ratio = r.ssvdag_seconds / r.svdag_seconds;
  r.byte_ratio = double(r.ussvdag_bytes) / double(r.svdag_bytes);
  r.compact_byte_ratio = double(r.ssvdag_bytes) / double(r.svdag_bytes);
  return r;
}

}  // namespace mv::bench

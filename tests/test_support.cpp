#include "test_support.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>

#include <unistd.h>

#include "io/mesh_source.h"
#include "reference.h"
#include "megavox/voxelize.h"
#include "voxel/build_steps.h"

namespace mv::test {

const std::vector<DeviceInfo>& all_devices() {
  static const std::vector<DeviceInfo> devices = list_devices();
  return devices;
}

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string temp_path(const std::string& name) {
  namespace fs = std::filesystem;
  struct Folder {
    fs::path path = fs::temp_directory_path() / ("megavox_test_" + std::to_string(::getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  };
  static const Folder folder;
  return (folder.path / name).string();
}

Device& shared_device(const DeviceInfo& info) {
  static std::map<std::string, std::unique_ptr<Device>> open;
  auto& slot = open[info.selector()];
  if (!slot) slot = Device::open({info.selector(), 0, false});
  return *slot;
}

std::string device_test_name(const ::testing::TestParamInfo<DeviceInfo>& p) {
  const DeviceInfo& d = p.param;
  std::string lname = d.name + " " + d.platform;
  for (auto& c : lname) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string tag = lname.find("pocl") != std::string::npos || lname.find("portable computing") != std::string::npos
                        ? "pocl"
                    : lname.find("llvmpipe") != std::string::npos ? "llvmpipe"
                                                                  : d.type;
  std::string sel = d.selector();
  for (auto& c : sel)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return tag + "_" + d.backend + "_" + sel;
}

std::string shared_data_path(const std::string& relative) {
  const char* env = std::getenv("MEGAVOX_TEST_DATA");
  std::filesystem::path data =
      env && *env ? std::filesystem::path(env) : std::filesystem::path(MEGAVOX_SOURCE_DIR) / ".." / "shared" / "data";
  return (data / relative).lexically_normal().string();
}

std::string shared_data_file(const std::string& relative) {
  std::string path = shared_data_path(relative);
  return std::filesystem::exists(path) ? path : "";
}

std::vector<float> mesh_grid_triangles(const std::string& path, uint32_t resolution, const GridPlacement& placement) {
  auto mesh = io::open_mesh(path);
  std::vector<uint32_t> idx, all;
  while (mesh->next_triangles(idx, 1u << 20)) all.insert(all.end(), idx.begin(), idx.end());
  Bounds b;
  for (uint32_t v : all) b.extend(mesh->positions()[3 * size_t{v}], mesh->positions()[3 * size_t{v} + 1],
                                  mesh->positions()[3 * size_t{v} + 2]);
  std::vector<float> tris;
  triangles_to_grid(grid_for_bounds(b, resolution, placement), mesh->positions(), all.data(), all.size() / 3, tris);
  return tris;
}

std::vector<float> octahedron_grid_triangles(uint32_t resolution, float bottom) {
  std::vector<float> pos = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, bottom};
  std::vector<uint32_t> idx = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  Bounds b;
  for (size_t i = 0; i < pos.size(); i += 3) b.extend(pos[i], pos[i + 1], pos[i + 2]);
  std::vector<float> tris;
  triangles_to_grid(grid_for_bounds(b, resolution), pos, idx.data(), idx.size() / 3, tris);
  return tris;
}

void write_ply(const std::string& path, const std::vector<float>& pos, const std::vector<uint32_t>& idx) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << pos.size() / 3
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << idx.size() / 3
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.write(reinterpret_cast<const char*>(pos.data()), static_cast<std::streamsize>(pos.size() * 4));
  for (size_t t = 0; t < idx.size(); t += 3) {
    unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(&idx[t]), 12);
  }
}

void write_obj(const std::string& path, std::span<const float> pos, const std::vector<uint32_t>& idx) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  for (size_t v = 0; v < pos.size(); v += 3) std::fprintf(f, "v %.9g %.9g %.9g\n", pos[v], pos[v + 1], pos[v + 2]);
  for (size_t t = 0; t < idx.size(); t += 3) std::fprintf(f, "f %u %u %u\n", idx[t] + 1, idx[t + 1] + 1, idx[t + 2] + 1);
  std::fclose(f);
}

std::vector<uint64_t> sorted_unique(std::vector<uint64_t> k) {
  std::sort(k.begin(), k.end());
  k.erase(std::unique(k.begin(), k.end()), k.end());
  return k;
}

// Voxel sets with little, some and much sharing (see test_support.h).
std::vector<std::pair<std::string, std::vector<uint64_t>>> voxel_sets(uint32_t levels) {
  const uint32_t n = 1u << levels;
  std::mt19937_64 rng(levels);
  std::vector<std::pair<std::string, std::vector<uint64_t>>> sets;
  std::vector<uint64_t> random, shell, tiled, planes;
  for (int i = 0; i < 3000; ++i) random.push_back(ref::morton3(rng() % n, rng() % n, rng() % n, 21));
  const double c = n / 2.0, r = n * 0.4;
  for (uint32_t x = 0; x < n; ++x)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t z = 0; z < n; ++z) {
        double d = std::sqrt((x + .5 - c) * (x + .5 - c) + (y + .5 - c) * (y + .5 - c) + (z + .5 - c) * (z + .5 - c));
        if (std::abs(d - r) < 0.9) shell.push_back(ref::morton3(x, y, z, 21));
        if (((x ^ y ^ z) & 3) == 0 && (x % 8) < 5) tiled.push_back(ref::morton3(x, y, z, 21));
        // axis-aligned faces, as in CAD parts: runs of equal nodes with symmetric masks
        if (x == n / 4 || y == 3 % n || (z == n - 2 && x < n / 2)) planes.push_back(ref::morton3(x, y, z, 21));
      }
  sets.push_back({"random", sorted_unique(random)});
  sets.push_back({"shell", sorted_unique(shell)});
  sets.push_back({"tiled", sorted_unique(tiled)});
  sets.push_back({"planes", sorted_unique(planes)});
  sets.push_back({"one voxel", {ref::morton3(n - 1, 0, n / 2, 21)}});
  return sets;
}

Dag host_dag(const std::vector<uint64_t>& voxels, uint32_t levels, bool reduce) {
  Dag d;
  d.levels = levels;
  d.reduced = reduce;
  d.voxels = voxels.size();
  d.level.resize(levels + 1);
  std::vector<uint64_t> keys = voxels;  // keys of level l - 1's nodes (level 0: the voxels)
  std::vector<uint32_t> ids(keys.size(), 0);  // their ids
  for (uint32_t l = 1; l <= levels; ++l) {
    DagLevel& lv = d.level[l];
    std::map<std::vector<uint32_t>, uint32_t> classes;
    std::vector<uint64_t> up;
    std::vector<uint32_t> up_ids;
    for (size_t i = 0; i < keys.size();) {
      const uint64_t parent = keys[i] >> 3;
      std::vector<uint32_t> sig{0};
      for (; i < keys.size() && keys[i] >> 3 == parent; ++i) {
        sig[0] |= 1u << (keys[i] & 7);
        if (l > 1) sig.push_back(ids[i]);
      }
      uint32_t id = static_cast<uint32_t>(lv.mask.size());
      auto [it, fresh] = reduce ? classes.emplace(sig, id) : std::make_pair(classes.end(), true);
      if (!fresh) id = it->second;
      if (fresh) {
        lv.mask.push_back(sig[0]);
        lv.first.push_back(static_cast<uint32_t>(lv.children.size()));
        lv.children.insert(lv.children.end(), sig.begin() + 1, sig.end());
      }
      up.push_back(parent);
      up_ids.push_back(id);
    }
    keys.swap(up);
    ids.swap(up_ids);
  }
  return d;
}

std::vector<uint32_t> random_u32(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint32_t> v(n);
  for (auto& x : v) x = static_cast<uint32_t>(rng());
  return v;
}

std::vector<uint64_t> random_u64(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> v(n);
  for (auto& x : v) x = rng();
  return v;
}

size_t expect_same_hits(const std::vector<RayHit>& got, const std::vector<RayHit>& want) {
  EXPECT_EQ(got.size(), want.size());
  size_t hits = 0;
  bool reported = false;  // the first ray that differs is reported, field by field; the rest only counted
  for (size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
    const RayHit &g = got[i], &w = want[i];
    hits += g.hit;
    bool same = g.hit == w.hit && !g.coarse && g.t == w.t && g.level == w.level && g.steps == w.steps;
    for (int a = 0; a < 3; ++a) same = same && g.cell[a] == w.cell[a] && g.normal[a] == w.normal[a];
    if (same || reported) continue;
    reported = true;
    SCOPED_TRACE("ray " + std::to_string(i));
    EXPECT_EQ(g.hit, w.hit);
    EXPECT_FALSE(g.coarse);
    EXPECT_EQ(g.t, w.t);
    EXPECT_EQ(g.level, w.level);
    EXPECT_EQ(g.steps, w.steps);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(g.cell[a], w.cell[a]);
      EXPECT_EQ(g.normal[a], w.normal[a]);
    }
  }
  return hits;
}

MvxFile unit_grid_file(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, Encoding e) {
  GridTransform grid;
  grid.resolution = 1u << levels;
  return mvx_for_dag(build_dag_for_format(dev, voxels, levels, e), e, grid, Bounds{});
}

}  // namespace mv::test

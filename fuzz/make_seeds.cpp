// Writes the committed seed corpus (fuzz/corpus/<target>/): a few small valid files per reader, made with
// the project's writers where it has them (.mvx, SymVox, .vdb) and by hand (PLY, LAS, OBJ), each read back
// through its reader before it is kept. Usage (not built by default):
//   cmake --build build-fuzz --target make_seeds && build-fuzz/make_seeds fuzz/corpus
// Every file comes out byte for byte the same but the .vdb ones, which carry a random file UUID.
// The DAGs come from a tiny CPU build (hash-consing, with reflections for the symmetric ones), checked by
// decoding every encoding back to the voxels it was made of.
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <string>
#include <vector>

#include "io/mesh_source.h"
#include "io/ply_reader.h"
#include "io/point_source.h"
#include "io/symvox_file.h"
#include "io/vdb_source.h"
#include "io/vdb_writer.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "job_request.h"
#include "mask_seeds.h"

namespace fs = std::filesystem;

namespace {

fs::path out_dir;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error("make_seeds: " + what);
}

std::string seed_path(const std::string& target, const std::string& name) {
  fs::create_directories(out_dir / target);
  return (out_dir / target / name).string();
}

std::string write_seed(const std::string& target, const std::string& name, const std::string& bytes) {
  const std::string p = seed_path(target, name);
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

void check_size(const std::string& path) {
  const auto bytes = fs::file_size(path);
  require(bytes < 64 * 1024, path + " has " + std::to_string(bytes) + " bytes (seeds stay under 64 KiB)");
  std::printf("  %-50s %6llu bytes\n", path.c_str(), static_cast<unsigned long long>(bytes));
}

// ---------------------------------------------------------------------------------------------------
// Little-endian (or big-endian) values

template <class T>
void put(std::string& out, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

void text(std::string& out, const std::string& s, size_t n) {
  std::string t = s.substr(0, n);
  t.resize(n, '\0');
  out += t;
}

// ---------------------------------------------------------------------------------------------------
// PLY

// A PLY body value of `type` in one format.
void ply_value(std::string& out, const std::string& format, const std::string& type, double v) {
  if (format == "ascii") {
    char t[40];
    const bool real = type == "float" || type == "double";
    std::snprintf(t, sizeof t, real ? "%.9g " : "%.0f ", v);
    out += t;
    return;
  }
  const bool big = format == "binary_big_endian";
  if (type == "char") put(out, static_cast<int8_t>(v), big);
  else if (type == "uchar") put(out, static_cast<uint8_t>(v), big);
  else if (type == "short") put(out, static_cast<int16_t>(v), big);
  else if (type == "ushort") put(out, static_cast<uint16_t>(v), big);
  else if (type == "int") put(out, static_cast<int32_t>(v), big);
  else if (type == "uint") put(out, static_cast<uint32_t>(v), big);
  else if (type == "float") put(out, static_cast<float>(v), big);
  else put(out, v, big);
}

void ply_end(std::string& out, const std::string& format) {
  if (format == "ascii") out.back() = '\n';
}

// A square pyramid (a quad and 4 triangles); `extras`: colours and a normal between the coordinates, a
// face property on each side of the index list, and skipped elements before, between and after.
std::string pyramid_ply(const std::string& format, const std::string& coord, const std::string& count,
                        const std::string& index, bool extras) {
  const double v[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
  const std::vector<std::vector<int>> faces = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  std::string h = "ply\nformat " + format + " 1.0\ncomment megavox fuzz seed\nobj_info pyramid\n", b;
  if (extras) {
    h += "element camera 1\nproperty list uchar float view\nproperty int id\n";
    ply_value(b, format, "uchar", 2);
    ply_value(b, format, "float", 0.5);
    ply_value(b, format, "float", -0.5);
    ply_value(b, format, "int", 7);
    ply_end(b, format);
  }
  h += "element vertex 5\nproperty " + coord + " x\n";
  if (extras) h += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float nx\n";
  h += "property " + coord + " y\nproperty " + coord + " z\n";
  for (int i = 0; i < 5; ++i) {
    ply_value(b, format, coord, v[i][0]);
    if (extras)
      for (double c : {10.0 * i, 255.0, 3.0, -0.25}) ply_value(b, format, c == -0.25 ? "float" : "uchar", c);
    ply_value(b, format, coord, v[i][1]);
    ply_value(b, format, coord, v[i][2]);
    ply_end(b, format);
  }
  if (extras) {
    h += "element edge 1\nproperty list uchar int vertex_pair\n";
    ply_value(b, format, "uchar", 2);
    ply_value(b, format, "int", 0);
    ply_value(b, format, "int", 4);
    ply_end(b, format);
  }
  h += "element face 5\n";
  if (extras) h += "property uchar flags\n";
  h += "property list " + count + " " + index + " vertex_indices\n";
  if (extras) h += "property float quality\n";
  for (const auto& f : faces) {
    if (extras) ply_value(b, format, "uchar", 1);
    ply_value(b, format, count, static_cast<double>(f.size()));
    for (int i : f) ply_value(b, format, index, i);
    if (extras) ply_value(b, format, "float", 0.75);
    ply_end(b, format);
  }
  if (extras) {
    h += "element material 1\nproperty uchar ambient\n";
    ply_value(b, format, "uchar", 9);
    ply_end(b, format);
  }
  return h + "end_header\n" + b;
}

// A point cloud: `n` vertices with the given properties (type, name), values from a simple pattern.
std::string cloud_ply(const std::string& format, const std::vector<std::pair<std::string, std::string>>& props,
                      int n, bool with_face) {
  std::string h = "ply\nformat " + format + " 1.0\ncomment megavox fuzz seed\nelement vertex " + std::to_string(n) + "\n",
              b;
  for (const auto& [type, name] : props) h += "property " + type + " " + name + "\n";
  for (int i = 0; i < n; ++i) {
    for (size_t k = 0; k < props.size(); ++k) {
      const std::string& type = props[k].first;
      const bool real = type == "float" || type == "double";
      double v = real ? (i * 0.37 - k * 1.5) : (i * 7 + k * 3) % 200;
      ply_value(b, format, type, v);
    }
    ply_end(b, format);
  }
  if (with_face) {
    h += "element face 1\nproperty list uchar int vertex_indices\n";
    ply_value(b, format, "uchar", 3);
    for (int k = 0; k < 3; ++k) ply_value(b, format, "int", k);
    ply_end(b, format);
  }
  return h + "end_header\n" + b;
}

void ply_seeds() {
  std::puts("fuzz_ply_mesh");
  struct M {
    const char* name;
    std::string bytes;
  } meshes[] = {
      {"pyramid_ascii.ply", pyramid_ply("ascii", "float", "uchar", "int", false)},
      {"pyramid_extras_ascii.ply", pyramid_ply("ascii", "double", "ushort", "uint", true)},
      {"pyramid_le.ply", pyramid_ply("binary_little_endian", "float", "uchar", "int", false)},
      {"pyramid_extras_le.ply", pyramid_ply("binary_little_endian", "float", "uchar", "uint", true)},
      {"pyramid_extras_be.ply", pyramid_ply("binary_big_endian", "double", "short", "ushort", true)},
      {"points_only_le.ply", cloud_ply("binary_little_endian", {{"float", "x"}, {"float", "y"}, {"float", "z"}}, 4, false)},
  };
  for (const auto& m : meshes) {
    const std::string p = write_seed("fuzz_ply_mesh", m.name, m.bytes);
    mv::io::PlyMeshReader r(p);
    std::vector<uint32_t> t;
    uint64_t n = 0;
    while (r.next_triangles(t, 3)) n += t.size() / 3;
    require(n == (r.info().faces ? 6u : 0u), p + ": triangles");
    check_size(p);
  }
  std::puts("fuzz_ply_points");
  using P = std::vector<std::pair<std::string, std::string>>;
  const P xyz_f = {{"float", "x"}, {"float", "y"}, {"float", "z"}};
  struct C {
    const char* name;
    std::string bytes;
  } clouds[] = {
      {"cloud_ascii.ply", cloud_ply("ascii", {{"float", "x"}, {"float", "y"}, {"float", "z"}, {"uchar", "red"},
                                               {"uchar", "green"}, {"uchar", "blue"}}, 6, false)},
      {"cloud_normals_le.ply", cloud_ply("binary_little_endian", {{"double", "x"}, {"double", "y"}, {"double", "z"},
                                                                  {"float", "nx"}, {"float", "ny"}, {"float", "nz"},
                                                                  {"ushort", "intensity"}}, 8, false)},
      {"cloud_ints_be.ply", cloud_ply("binary_big_endian", {{"int", "x"}, {"int", "y"}, {"int", "z"}, {"ushort", "r"},
                                                            {"ushort", "g"}, {"ushort", "b"}}, 5, false)},
      {"cloud_with_face_le.ply", cloud_ply("binary_little_endian", xyz_f, 4, true)},
      {"pyramid_extras_ascii.ply", pyramid_ply("ascii", "double", "ushort", "uint", true)},
  };
  for (const auto& c : clouds) {
    const std::string p = write_seed("fuzz_ply_points", c.name, c.bytes);
    auto src = mv::io::open_points(p);
    mv::PointColumns pts;
    while (src->next(pts, 2)) {
    }
    require(pts.size() == src->info().points && pts.size() > 0, p + ": points");
    check_size(p);
  }
}

// ---------------------------------------------------------------------------------------------------
// LAS (the ASPRS layout of LAS 1.0-1.4, as tests/point_fixture.cpp writes it)

uint16_t las_record_length(int format) {
  static constexpr uint16_t kLength[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  return kLength[format];
}

std::string vlr(bool extended, uint16_t record_id, const std::string& payload) {
  std::string b;
  put<uint16_t>(b, 0);
  text(b, "LASF_Projection", 16);
  put<uint16_t>(b, record_id);
  if (extended) put<uint64_t>(b, payload.size());
  else put<uint16_t>(b, static_cast<uint16_t>(payload.size()));
  text(b, "megavox fuzz seed", 32);
  return b + payload;
}

std::string geokeys(uint16_t crs) {
  std::string b;
  for (uint16_t w : {1, 1, 0, 3, 1024, 0, 1, 1, 2048, 0, 1, 4269, 3072, 0, 1}) put(b, w);
  put(b, crs);
  return b;
}

struct LasSpec {
  int minor = 2, format = 3, points = 3;
  uint16_t extra = 0;
  std::string wkt;
  bool wkt_in_evlr = false;
  uint16_t geokey_crs = 0;
};

std::string make_las(const LasSpec& s) {
  const uint16_t header = s.minor >= 4 ? 375 : s.minor == 3 ? 235 : 227;
  const uint16_t record = static_cast<uint16_t>(las_record_length(s.format) + s.extra);
  std::vector<std::string> vlrs;
  if (!s.wkt.empty() && !s.wkt_in_evlr) vlrs.push_back(vlr(false, 2112, s.wkt + '\0'));
  if (s.geokey_crs) vlrs.push_back(vlr(false, 34735, geokeys(s.geokey_crs)));
  size_t vlr_bytes = 0;
  for (const auto& v : vlrs) vlr_bytes += v.size();
  const uint32_t point_offset = static_cast<uint32_t>(header + vlr_bytes);
  const uint64_t n = static_cast<uint64_t>(s.points);
  const bool count64 = s.minor >= 4 && s.format >= 6;
  std::string b = "LASF";
  put<uint16_t>(b, 7);
  put<uint16_t>(b, s.minor >= 4 && !s.wkt.empty() ? 16 : 0);
  text(b, "", 16);
  put<uint8_t>(b, 1);
  put<uint8_t>(b, static_cast<uint8_t>(s.minor));
  text(b, "megavox fuzz seed", 32);
  text(b, "make_seeds", 32);
  put<uint16_t>(b, 100);
  put<uint16_t>(b, 2024);
  put<uint16_t>(b, header);
  put<uint32_t>(b, point_offset);
  put<uint32_t>(b, static_cast<uint32_t>(vlrs.size()));
  put<uint8_t>(b, static_cast<uint8_t>(s.format));
  put<uint16_t>(b, record);
  put<uint32_t>(b, count64 ? 0 : static_cast<uint32_t>(n));
  for (int r = 0; r < 5; ++r) put<uint32_t>(b, r == 0 && !count64 ? static_cast<uint32_t>(n) : 0);
  const double scale[3] = {0.01, 0.001, 0.25}, offset[3] = {636000.5, -20, 3};
  for (double v : scale) put(b, v);
  for (double v : offset) put(b, v);
  for (int a = 0; a < 3; ++a) {
    put(b, offset[a] + 1000);
    put(b, offset[a] - 1000);
  }
  if (s.minor >= 3) put<uint64_t>(b, 0);
  size_t evlr_start_at = 0;
  if (s.minor >= 4) {
    evlr_start_at = b.size();
    put<uint64_t>(b, 0);
    put<uint32_t>(b, !s.wkt.empty() && s.wkt_in_evlr ? 1 : 0);
    put<uint64_t>(b, n);
    for (int r = 0; r < 15; ++r) put<uint64_t>(b, r == 0 ? n : 0);
  }
  require(b.size() == header, "LAS header size");
  for (const auto& v : vlrs) b += v;
  const int f = s.format;
  for (uint64_t i = 0; i < n; ++i) {
    const size_t start = b.size();
    for (int a = 0; a < 3; ++a) put<int32_t>(b, static_cast<int32_t>(i * 1000 + a * 37 - 500));
    put<uint16_t>(b, static_cast<uint16_t>(i * 300));
    if (f < 6) {
      for (uint8_t v : {0x11, 2, 0xf4, 9}) put<uint8_t>(b, v);
      put<uint16_t>(b, 77);
      if (f == 1 || f == 3) put<double>(b, i * 0.5);
      if (f == 2 || f == 3)
        for (int c = 0; c < 3; ++c) put<uint16_t>(b, static_cast<uint16_t>(i * 1000 + c));
    } else {
      for (uint8_t v : {0x11, 0x40, 2, 9}) put<uint8_t>(b, v);
      put<int16_t>(b, -1200);
      put<uint16_t>(b, 77);
      put<double>(b, i * 0.5);
      if (f >= 7)
        for (int c = 0; c < 3; ++c) put<uint16_t>(b, static_cast<uint16_t>(i * 1000 + c));
      if (f == 8) put<uint16_t>(b, 5);
    }
    b.resize(start + las_record_length(f), 'w');
    for (uint16_t k = 0; k < s.extra; ++k) put<uint8_t>(b, static_cast<uint8_t>(i + k));
  }
  if (!s.wkt.empty() && s.wkt_in_evlr) {
    const uint64_t at = b.size();
    std::memcpy(b.data() + evlr_start_at, &at, 8);
    b += vlr(true, 2112, s.wkt + '\0');
  }
  return b;
}

void las_seeds() {
  std::puts("fuzz_las");
  const std::string wkt = "PROJCS[\"NAD83 / Oregon GIC Lambert (ft)\",GEOGCS[\"NAD83\"],UNIT[\"foot\",0.3048]]";
  struct L {
    const char* name;
    LasSpec spec;
  } files[] = {
      {"las10_format0.las", {.minor = 0, .format = 0, .points = 4}},
      {"las12_format3_geokeys.las", {.minor = 2, .format = 3, .points = 3, .geokey_crs = 2992}},
      {"las13_format1_extra.las", {.minor = 3, .format = 1, .points = 3, .extra = 5}},
      {"las14_format6_wkt_evlr.las", {.minor = 4, .format = 6, .points = 3, .wkt = wkt, .wkt_in_evlr = true}},
      {"las14_format8_wkt_vlr.las", {.minor = 4, .format = 8, .points = 2, .extra = 2, .wkt = wkt}},
      {"las12_format2_empty.las", {.minor = 2, .format = 2, .points = 0}},
  };
  for (const auto& l : files) {
    const std::string p = write_seed("fuzz_las", l.name, make_las(l.spec));
    auto src = mv::io::open_points(p);
    mv::PointColumns pts;
    while (src->next(pts, 2)) {
    }
    require(pts.size() == static_cast<uint64_t>(l.spec.points), p + ": points");
    check_size(p);
  }
}

// ---------------------------------------------------------------------------------------------------
// DAGs, built on the CPU from Morton keys (x + 2y + 4z per level)

uint64_t morton(uint32_t x, uint32_t y, uint32_t z) {
  uint64_t k = 0;
  for (int b = 0; b < 21; ++b)
    k |= uint64_t(x >> b & 1) << (3 * b) | uint64_t(y >> b & 1) << (3 * b + 1) | uint64_t(z >> b & 1) << (3 * b + 2);
  return k;
}

// Levels bottom-up. `reduced`: identical subtrees stored once (a DAG; else the plain octree). `symmetric`:
// also subtrees equal up to a reflection, the pointer tagged with it (octant c of the stored node is octant
// c ^ tag of the child); the root is stored as it is.
mv::Dag build_dag(std::vector<uint64_t> keys, uint32_t levels, bool reduced, bool symmetric) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  mv::Dag dag;
  dag.levels = levels;
  dag.reduced = reduced;
  dag.symmetric = symmetric;
  dag.voxels = keys.size();
  dag.level.resize(levels + 1);
  for (uint32_t l = 0; l <= levels; ++l) {
    std::vector<uint64_t> p;
    for (uint64_t k : keys) p.push_back(k >> (3 * l));
    p.erase(std::unique(p.begin(), p.end()), p.end());
    dag.svo_nodes.push_back(p.size());
  }
  struct Ref {
    uint32_t id, tag;
  };
  // Nodes of the level below, by prefix: (prefix, reference).
  std::vector<std::pair<uint64_t, Ref>> below;
  for (uint32_t l = 1; l <= levels; ++l) {
    // Group what is below (voxels at l = 1) by prefix >> 3.
    std::vector<std::pair<uint64_t, std::vector<std::pair<uint32_t, Ref>>>> groups;  // prefix, (octant, child)
    if (l == 1) {
      for (uint64_t k : keys) {
        if (groups.empty() || groups.back().first != k >> 3) groups.push_back({k >> 3, {}});
        groups.back().second.push_back({static_cast<uint32_t>(k & 7), {0, 0}});
      }
    } else {
      for (const auto& [prefix, ref] : below) {
        if (groups.empty() || groups.back().first != prefix >> 3) groups.push_back({prefix >> 3, {}});
        groups.back().second.push_back({static_cast<uint32_t>(prefix & 7), ref});
      }
    }
    mv::DagLevel& lv = dag.level[l];
    std::map<std::vector<uint32_t>, uint32_t> stored;
    std::vector<std::pair<uint64_t, Ref>> here;
    for (const auto& [prefix, kids] : groups) {
      // The node's content reflected by t: mask, then (child id, tag) in octant order.
      auto content = [&, &kids = kids](uint32_t t) {
        std::vector<std::pair<uint32_t, Ref>> r;
        for (const auto& [o, ref] : kids) r.push_back({o ^ t, {ref.id, ref.tag ^ t}});
        std::sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<uint32_t> c = {0};
        for (const auto& [o, ref] : r) {
          c[0] |= 1u << o;
          if (l > 1) c.insert(c.end(), {ref.id, symmetric ? ref.tag : 0});
        }
        return c;
      };
      uint32_t best_t = 0;
      std::vector<uint32_t> best = content(0);
      if (symmetric && l < levels)
        for (uint32_t t = 1; t < 8; ++t)
          if (auto c = content(t); c < best) best = c, best_t = t;
      uint32_t id;
      auto it = reduced ? stored.find(best) : stored.end();
      if (it != stored.end()) {
        id = it->second;
      } else {
        id = static_cast<uint32_t>(lv.mask.size());
        if (reduced) stored.emplace(best, id);
        lv.mask.push_back(best[0]);
        if (l > 1) {
          lv.first.push_back(static_cast<uint32_t>(lv.children.size()));
          for (size_t k = 1; k < best.size(); k += 2) {
            lv.children.push_back(best[k]);
            if (symmetric) lv.tags.push_back(best[k + 1]);
          }
        }
      }
      here.push_back({prefix, {id, best_t}});
    }
    below = std::move(here);
  }
  require(dag.level[levels].mask.size() == 1, "one root");
  return dag;
}

// A few shapes in a 2^levels grid: a plane, a diagonal, a mirrored pair of blocks, a sphere shell.
std::vector<uint64_t> sample_voxels(uint32_t levels) {
  const uint32_t n = 1u << levels;
  std::vector<uint64_t> v;
  for (uint32_t x = 0; x < n; ++x)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t z = 0; z < n; ++z) {
        const int dx = 2 * int(x) - int(n) + 1, dy = 2 * int(y) - int(n) + 1, dz = 2 * int(z) - int(n) + 1;
        const int r2 = dx * dx + dy * dy + dz * dz, R = int(n) - 2;
        const bool shell = r2 <= R * R && r2 > (R - 3) * (R - 3);
        const bool plane = y == 1 && x < n / 2;
        const bool diag = x == y && y == z;
        const bool blocks = z < 2 && y < 3 && (x < 2 || x >= n - 2);
        if (shell || plane || diag || blocks) v.push_back(morton(x, y, z));
      }
  std::sort(v.begin(), v.end());
  return v;
}

mv::MvxFile mvx_of(const mv::Dag& dag, const mv::EncodedDag& enc) {
  mv::MvxFile f;
  f.grid.resolution = 1u << dag.levels;
  f.grid.voxel_size = 0.25;
  f.grid.origin[0] = -1;
  f.grid.origin[2] = 2;
  f.bounds.extend(-1, 0, 2);
  f.bounds.extend(-1 + 0.25 * f.grid.resolution, 1, 3);
  f.voxels = dag.voxels;
  f.svo_nodes = dag.svo_nodes;
  f.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= dag.levels; ++l) f.dag_nodes.push_back(dag.nodes(l));
  f.dag = enc;
  return f;
}

mv::PointHierarchy sample_points(bool all_columns) {
  mv::PointHierarchy h;
  h.source.format = "make_seeds";
  h.source.points = 6;
  h.source.attributes = all_columns ? mv::kPointRgb | mv::kPointNormal | mv::kPointIntensity | mv::kPointExtra
                                    : mv::kPointIntensity;
  h.source.extra_bytes = all_columns ? 3 : 0;
  h.source.crs = all_columns ? "EPSG:2992" : "";
  h.source.z_up = all_columns;
  for (int a = 0; a < 3; ++a) h.source.scale[a] = 0.5, h.source.offset[a] = 10.0 * a;
  h.shift = -18;
  h.depth = 1;
  h.grid_bits = 6;
  // The root keeps one representative; two leaves (octants 0 and 5) hold 3 and 2 points; one point dropped.
  mv::PointNode root;
  root.code = 1;
  root.first_point = 0;
  root.point_count = 1;
  root.subtree_points = 5;
  root.first_child = 1;
  root.child_mask = 1 | 1 << 5;
  mv::PointNode a, b;
  a.code = 8 | 0, a.level = 1, a.first_point = 1, a.point_count = 3, a.subtree_points = 3;
  b.code = 8 | 5, b.level = 1, b.first_point = 4, b.point_count = 2, b.subtree_points = 2;
  h.nodes = {root, a, b};
  h.nodes_per_level = {1, 2};
  const int32_t xyz[6][3] = {{1, 1, 1}, {0, 0, 0}, {1, 2, 3}, {3, 0, 1}, {5, 1, 6}, {7, 3, 4}};
  for (const auto& p : xyz) {
    h.points.xyz.insert(h.points.xyz.end(), {p[0], p[1], p[2]});
    h.points.intensity.push_back(static_cast<uint16_t>(p[0] * 100));
    if (all_columns) {
      h.points.rgb.insert(h.points.rgb.end(), {uint16_t(p[0] * 30), uint16_t(p[1] * 30), uint16_t(p[2] * 30)});
      h.points.normal.insert(h.points.normal.end(), {0.0f, 1.0f, 0.0f});
      h.points.extra.insert(h.points.extra.end(), {uint8_t(p[0]), uint8_t(p[1]), uint8_t(p[2])});
    }
  }
  h.points_in = 6;
  h.points_kept = 5;
  h.points_dropped = 1;
  return h;
}

void dag_seeds() {
  std::puts("fuzz_mvx, fuzz_symvox");
  for (uint32_t levels : {3u, 4u}) {
    const std::vector<uint64_t> voxels = sample_voxels(levels);
    const std::string L = std::to_string(levels);
    const mv::Dag plain = build_dag(voxels, levels, true, false);
    const mv::Dag svo = build_dag(voxels, levels, false, false);
    const mv::Dag sym = build_dag(voxels, levels, true, true);
    const mv::EncodedDag e_svdag = mv::encode_svdag(plain), e_svo = mv::encode_svdag(svo);
    const mv::EncodedDag e_ussvdag = mv::encode_svdag(sym), e_ssvdag = mv::encode_ssvdag(sym);
    for (const mv::EncodedDag* e : {&e_svdag, &e_svo, &e_ussvdag, &e_ssvdag})
      require(mv::decode_encoded(*e) == voxels, "a CPU-built DAG decodes to its voxels (" + mv::encoding_name(e->encoding) + ")");
    require(sym.nodes(1) < plain.nodes(1), "the symmetric DAG merges reflections");
    if (levels == 3) {  // the .mvx seeds: 4 KiB pages make them 16-20 KiB whatever the grid
      // Every encoding paged in 16-word pages (so several pages; the ussvdag in level order, its pointers
      // relative), one svdag and one ssvdag unpaged.
      const mv::MvxPaging small{16, mv::NodeOrder::subtree}, unpaged{0, mv::NodeOrder::level};
      for (const auto& [name, dag, enc, paging] :
           {std::tuple{"svdag", &plain, &e_svdag, small}, {"svo", &svo, &e_svo, small},
            {"ussvdag", &sym, &e_ussvdag, mv::MvxPaging{16, mv::NodeOrder::level}}, {"ssvdag", &sym, &e_ssvdag, unpaged},
            {"ssvdag_paged", &sym, &e_ssvdag, small},
            {"svdag_unpaged", &plain, &e_svdag, unpaged}}) {
        const std::string p = seed_path("fuzz_mvx", std::string("voxels_") + name + ".mvx");
        mv::write_mvx(p, mvx_of(*dag, *enc), paging);
        require(mv::decode_encoded(mv::read_mvx(p).dag) == voxels, p + ": voxels");
        check_size(p);
      }
      for (bool all : {false, true}) {
        const std::string p = seed_path("fuzz_mvx", all ? "points_all_columns.mvx" : "points_intensity.mvx");
        mv::write_mvx_points(p, sample_points(all));
        require(mv::read_mvx_points(p).points.size() == 6, p + ": points");
        check_size(p);
      }
    }
    for (const auto& [ext, enc] : {std::pair{"svdag", &e_svdag}, {"ussvdag", &e_ussvdag}, {"ssvdag", &e_ssvdag}}) {
      mv::io::SymvoxFile f;
      for (int a = 0; a < 3; ++a) f.bbox_min[a] = -1.0f + a, f.bbox_max[a] = 1.0f + a;
      f.root_side = 2;
      f.levels = levels;
      f.nodes = static_cast<uint32_t>(enc == &e_svdag ? plain.nodes(levels - 1) : sym.nodes(levels - 1));
      f.dag = *enc;
      const std::string p = seed_path("fuzz_symvox", "grid" + L + "." + ext);
      mv::io::write_symvox(p, f);
      const mv::io::SymvoxFile back = mv::io::read_symvox(p);
      require(back.dag.encoding == enc->encoding && mv::decode_encoded(back.dag) == voxels, p + ": layout and voxels");
      check_size(p);
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// OBJ (assimp) and VDB

void obj_seeds() {
  std::puts("fuzz_mesh_assimp");
  const std::pair<const char*, const char*> objs[] = {
      {"triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"quad_cube.obj",
       "# a unit cube of quads\no cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
       "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"},
      {"normals_uvs_groups.obj",
       "g left\nv -1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 1 1 1\nf 1/1/1 2/2/1 3/3/1\n"
       "g right\nv 1 0 0\nv 2 1 0\nv 2 0 1\nusemtl none\nf 4//1 5//1 6//1\ns 1\n"},
      {"negative_indices_lines.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\nf -4 -3 -2\nf -4 -2 -1\nl 1 2\np 3\n"},
      {"ply_by_content.obj", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
  };
  for (const auto& [name, body] : objs) {
    const std::string p = write_seed("fuzz_mesh_assimp", name, body);
    auto mesh = mv::io::open_mesh(p);
    std::vector<uint32_t> t;
    uint64_t n = 0;
    while (mesh->next_triangles(t, 4)) n += t.size() / 3;
    require(n > 0, p + ": triangles");
    check_size(p);
  }
}

void vdb_seeds() {
  std::puts("fuzz_vdb");
  openvdb::initialize();
  auto write = [](const std::string& name, openvdb::GridPtrVec grids, uint32_t compression) {
    const std::string p = seed_path("fuzz_vdb", name);
    openvdb::io::File file(p);
    file.setCompression(compression);
    file.write(grids);
    file.close();
    return p;
  };
  std::vector<std::string> paths;
  // The project's own writer: a mask grid "voxels" (what `megavox export --format vdb` writes).
  {
    const std::string p = seed_path("fuzz_vdb", "mask_megavox_export.vdb");
    mv::GridTransform g;
    g.resolution = 8;
    g.voxel_size = 0.5;
    mv::io::write_voxel_grid(p, {morton(0, 0, 0), morton(1, 0, 0), morton(3, 2, 1), morton(7, 7, 7)}, g, false);
    paths.push_back(p);
  }
  {
    auto ball = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(2, 2, 2), 0.5f, 1.5f);
    ball->setName("ball");
    paths.push_back(write("level_set_active_mask.vdb", {ball}, openvdb::io::COMPRESS_ACTIVE_MASK));
  }
  {
    auto fog = openvdb::FloatGrid::create(0.0f);
    fog->setName("density");
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    fog->tree().setValue(openvdb::Coord(1, 2, 3), 0.5f);
    fog->tree().setValue(openvdb::Coord(-4, 2, 3), 1.0f);
    fog->tree().setValue(openvdb::Coord(0, 0, 0), 0.0f);
    fog->tree().addTile(1, openvdb::Coord(16, 0, 0), 0.25f, true);  // an active 8^3 tile
    auto flags = openvdb::BoolGrid::create(false);
    flags->setName("flags");
    flags->tree().setValue(openvdb::Coord(5, 5, 5), true);
    flags->tree().setValueOn(openvdb::Coord(6, 5, 5), false);
    paths.push_back(write("fog_tile_and_bool_zip.vdb", {fog, flags}, openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK));
    paths.push_back(write("fog_tile_and_bool_active_mask.vdb", {fog, flags}, openvdb::io::COMPRESS_ACTIVE_MASK));
  }
  {
    auto mask = openvdb::MaskGrid::create();
    mask->setName("m");
    mask->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
    for (int i = 0; i < 6; ++i) mask->tree().setValueOn(openvdb::Coord(i, 2 * i, -i));
    paths.push_back(write("mask_active_mask.vdb", {mask}, openvdb::io::COMPRESS_ACTIVE_MASK));
  }
  for (const std::string& p : paths) {
    require(!mv::io::read_vdb(p, "", 0).keys.empty(), p + ": voxels");
    check_size(p);
  }
}

// Jobs of `megavox serve`: a build by name, a full build, renders of a scene (preset and camera) and of a file,
// a point-cloud tileset, masks from a box and from a seed map with a model.
void job_seeds() {
  std::puts("fuzz_job_request");
  const std::pair<const char*, const char*> jobs[] = {
      {"build_by_name.json", R"({"kind":"build","input":"meshes/bunny.ply"})"},
      {"build_all_fields.json",
       R"({"kind":"build","input":"a/b.obj","resolution":1024,"format":"ssvdag","voxelize":"thin","grid_origin":"min"})"},
      {"render_scene.json", R"({"kind":"render","scene":"00ff00ff00ff00ff","width":640,"height":480,"view":"top","shading":"normal"})"},
      {"render_file.json", "{ \"kind\" : \"render\", \"input\" : \"scene.mvx\", \"shading\" : \"heat\" }\n"},
      {"render_camera.json",
       R"({"kind":"render","scene":"00ff00ff00ff00ff","eye":[1,2,3],"target":[0,0.5,0],"up":[0,1,0],"fov":30})"},
      {"points_3dtiles.json", R"({"kind":"points","input":"scan.las","format":"3dtiles","depth":8,"max_node_points":500})"},
      {"mask_rect.json", R"({"kind":"mask","input":"photo.png","rect":[10,20,300,200],"iterations":3,"erode":0})"},
      {"mask_seeds_model.json", R"({"kind":"mask","input":"scan.pgm","seeds":"trimap.png","model":"statue.mvm"})"},
  };
  for (const auto& [name, body] : jobs) {
    const std::string p = write_seed("fuzz_job_request", name, body);
    mv::serve::parse_job_request(body);
    check_size(p);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds OUT_DIR (e.g. fuzz/corpus)\n");
    return 2;
  }
  out_dir = argv[1];
  try {
    ply_seeds();
    las_seeds();
    dag_seeds();
    obj_seeds();
    vdb_seeds();
    job_seeds();
    mask_seeds::write(out_dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}

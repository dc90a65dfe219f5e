// Mesh voxel colours on every device: vertex colours (PLY uchar and ushort, OBJ through assimp) and textures through
// the whole build against ref::mesh_voxel_colours (every voxel of each triangle alone, the nearest point by plain
// loops) and ref::preorder_colours for the depth-first array; geometry unchanged by colour; out of core equal to in
// core; the refusals.
#include <cmath>
#include <cstdio>
#include <fstream>

#include "colour_reference.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/image.h"
#include "megavox/mvx.h"
#include "megavox/voxelize.h"
#include "test_support.h"
#include "voxel/mesh_colours.h"

namespace mv::test {
namespace {

class MeshColourTest : public ::testing::TestWithParam<DeviceInfo> {};

// An octahedron subdivided twice onto a sphere (128 triangles) of radius 0.9, with a colour per vertex from a hash
// of its index: neighbouring voxels take different triangles' colours, and ties between triangles sharing an edge
// or a corner go to the lower index.
struct ColourMesh {
  std::vector<float> pos;
  std::vector<uint32_t> idx;
  std::vector<uint32_t> rgb16;  // 3 channels per vertex, 16-bit
};

ColourMesh colour_sphere(int rounds = 2) {
  ColourMesh m;
  m.pos = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  m.idx = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  for (int round = 0; round < rounds; ++round) {
    std::vector<uint32_t> next;
    auto mid = [&](uint32_t a, uint32_t b) {
      float p[3];
      double len = 0;
      for (int k = 0; k < 3; ++k) p[k] = (m.pos[3 * a + k] + m.pos[3 * b + k]) / 2, len += double(p[k]) * p[k];
      for (int k = 0; k < 3; ++k) m.pos.push_back(float(p[k] / std::sqrt(len)));
      return uint32_t(m.pos.size() / 3 - 1);
    };
    for (size_t t = 0; t < m.idx.size(); t += 3) {
      const uint32_t a = m.idx[t], b = m.idx[t + 1], c = m.idx[t + 2];
      const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    m.idx = next;
  }
  for (float& p : m.pos) p *= 0.9f;
  for (uint32_t v = 0; v < m.pos.size() / 3; ++v) {
    const uint32_t h = (v + 1) * 2654435761u;
    for (int k = 0; k < 3; ++k) m.rgb16.push_back((h >> (5 * k + 3)) & 0xffff);
  }
  return m;
}

// A binary PLY with red, green and blue as uchar (the high bytes) or ushort.
std::string write_colour_ply(const ColourMesh& m, const std::string& name, bool wide) {
  const std::string path = temp_path(name);
  std::ofstream out(path, std::ios::binary);
  const char* type = wide ? "ushort" : "uchar";
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << m.pos.size() / 3
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty " << type << " red\nproperty " << type
      << " green\nproperty " << type << " blue\nelement face " << m.idx.size() / 3
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t v = 0; v < m.pos.size() / 3; ++v) {
    out.write(reinterpret_cast<const char*>(&m.pos[3 * v]), 12);
    for (int k = 0; k < 3; ++k) {
      const uint16_t c = static_cast<uint16_t>(m.rgb16[3 * v + k]);
      const uint8_t hi = static_cast<uint8_t>(c >> 8);
      if (wide) out.write(reinterpret_cast<const char*>(&c), 2);
      else out.write(reinterpret_cast<const char*>(&hi), 1);
    }
  }
  for (size_t t = 0; t < m.idx.size(); t += 3) {
    const unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(&m.idx[t]), 12);
  }
  return path;
}

// The same as ASCII, uchar colours.
std::string write_colour_ply_ascii(const ColourMesh& m, const std::string& name) {
  const std::string path = temp_path(name);
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << m.pos.size() / 3
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
         "property uchar blue\nelement face "
      << m.idx.size() / 3 << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.precision(9);
  for (size_t v = 0; v < m.pos.size() / 3; ++v)
    out << m.pos[3 * v] << " " << m.pos[3 * v + 1] << " " << m.pos[3 * v + 2] << " " << (m.rgb16[3 * v] >> 8) << " "
        << (m.rgb16[3 * v + 1] >> 8) << " " << (m.rgb16[3 * v + 2] >> 8) << "\n";
  for (size_t t = 0; t < m.idx.size(); t += 3) out << "3 " << m.idx[t] << " " << m.idx[t + 1] << " " << m.idx[t + 2] << "\n";
  return path;
}

BuildReport build_mesh(Device& dev, const std::string& in, const std::string& out, Encoding e, Attributes a,
                       uint32_t cube = 1024) {
  BuildOptions o;
  o.input = in;
  o.output = out;
  o.resolution = 64;
  o.cube = cube;
  o.encoding = e;
  o.attributes = a;
  return build_mvx(dev, o);
}

// The depth-first colours of voxels of one colour each, on a grid of 2^levels (ref::preorder_colours).
std::vector<uint8_t> depth_first_bytes(const ref::MeshVoxelColours& voxels, uint32_t levels) {
  std::vector<uint32_t> cells;
  for (uint64_t key : voxels.keys) {
    uint32_t c[3] = {0, 0, 0};
    for (int bit = 0; bit < 21; ++bit)
      for (int k = 0; k < 3; ++k) c[k] |= uint32_t(key >> (3 * bit + k) & 1) << bit;
    cells.insert(cells.end(), c, c + 3);
  }
  std::vector<uint8_t> bytes;
  for (const ref::ColourNode& n : ref::preorder_colours(cells, voxels.rgb, levels))
    bytes.insert(bytes.end(), n.rgb, n.rgb + 3);
  return bytes;
}

// The depth-first colours the rule gives for `m` on the grid of `r`.
std::vector<uint8_t> expected_colours(const ColourMesh& m, const BuildReport& r, std::vector<uint64_t>& keys) {
  std::vector<float> tris;
  triangles_to_grid(r.grid, m.pos, m.idx.data(), m.idx.size() / 3, tris);
  std::vector<uint32_t> tri_rgb;
  for (uint32_t v : m.idx)
    tri_rgb.push_back((m.rgb16[3 * v] >> 8) | (m.rgb16[3 * v + 1] >> 8) << 8 | (m.rgb16[3 * v + 2] >> 8) << 16);
  const ref::MeshVoxelColours want = ref::mesh_voxel_colours(tris, tri_rgb, r.grid.resolution);
  keys = want.keys;
  return depth_first_bytes(want, 6);
}

TEST_P(MeshColourTest, VertexColoursFollowTheNearestPointRule) {
  Device& dev = shared_device(GetParam());
  const ColourMesh m = colour_sphere();
  const std::string narrow = write_colour_ply(m, "sphere_rgb8.ply", false);
  const std::string wide = write_colour_ply(m, "sphere_rgb16.ply", true);
  const std::string ascii = write_colour_ply_ascii(m, "sphere_text.ply");
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag, Encoding::ussvdag, Encoding::svo}) {
    SCOPED_TRACE(encoding_name(e));
    const std::string out = temp_path("sphere_" + encoding_name(e) + ".mvx");
    const BuildReport r = build_mesh(dev, narrow, out, e, Attributes::automatic);
    EXPECT_EQ(r.attributes, "rgb");
    const MvxFile f = read_mvx(out);
    std::vector<uint64_t> keys;
    const std::vector<uint8_t> want = expected_colours(m, r, keys);
    EXPECT_EQ(decode_encoded(f.dag), keys);
    ASSERT_EQ(f.colours.size(), want.size());
    size_t differ = 0;
    for (size_t i = 0; i < want.size(); ++i) differ += f.colours[i] != want[i];
    EXPECT_EQ(differ, 0u);
    // geometry as without colour; ushort colours keep their high bytes: the same file
    const std::string grey = temp_path("sphere_grey_" + encoding_name(e) + ".mvx");
    const BuildReport g = build_mesh(dev, narrow, grey, e, Attributes::none);
    EXPECT_EQ(g.attributes, "none");
    EXPECT_EQ(g.nodes_per_level, r.nodes_per_level);
    EXPECT_EQ(read_mvx(grey).dag.words, f.dag.words);
    EXPECT_TRUE(read_mvx(grey).colours.empty());
    const std::string out16 = temp_path("sphere16_" + encoding_name(e) + ".mvx");
    build_mesh(dev, wide, out16, e, Attributes::rgb);
    EXPECT_EQ(read_mvx(out16).colours, f.colours);
    const std::string text = temp_path("sphere_text_" + encoding_name(e) + ".mvx");
    build_mesh(dev, ascii, text, e, Attributes::rgb);
    EXPECT_EQ(read_mvx(text).colours, f.colours);
  }
}

TEST_P(MeshColourTest, AssimpVertexColoursMatchThePly) {
  Device& dev = shared_device(GetParam());
  ColourMesh m = colour_sphere();
  for (uint32_t& c : m.rgb16) c &= 0xff00;  // whole bytes: the OBJ's c / 255 rounds back exactly
  const std::string ply = write_colour_ply(m, "sphere_obj_ref.ply", false);
  const std::string obj = temp_path("sphere_rgb.obj");
  {
    std::FILE* f = std::fopen(obj.c_str(), "w");
    for (size_t v = 0; v < m.pos.size() / 3; ++v)
      std::fprintf(f, "v %.9g %.9g %.9g %.9g %.9g %.9g\n", m.pos[3 * v], m.pos[3 * v + 1], m.pos[3 * v + 2],
                   (m.rgb16[3 * v] >> 8) / 255.0, (m.rgb16[3 * v + 1] >> 8) / 255.0, (m.rgb16[3 * v + 2] >> 8) / 255.0);
    for (size_t t = 0; t < m.idx.size(); t += 3)
      std::fprintf(f, "f %u %u %u\n", m.idx[t] + 1, m.idx[t + 1] + 1, m.idx[t + 2] + 1);
    std::fclose(f);
  }
  const std::string a = temp_path("sphere_obj.mvx"), b = temp_path("sphere_ply.mvx");
  EXPECT_EQ(build_mesh(dev, obj, a, Encoding::svdag, Attributes::automatic).attributes, "rgb");
  build_mesh(dev, ply, b, Encoding::svdag, Attributes::automatic);
  const MvxFile fa = read_mvx(a), fb = read_mvx(b);
  EXPECT_FALSE(fa.colours.empty());
  EXPECT_EQ(fa.colours, fb.colours);
  EXPECT_EQ(fa.dag.words, fb.dag.words);
}

// A folded strip of triangles over [0, 1]^3 with texture coordinates past 1 (the texture repeats), its material's
// diffuse map an 8 x 6 PNG of random texels beside the OBJ: each voxel samples the texture bilinearly.
TEST_P(MeshColourTest, TexturesAreSampledBilinearly) {
  Device& dev = shared_device(GetParam());
  ref::RefTexture tex;
  tex.width = 8;
  tex.height = 6;
  Image png;
  png.width = tex.width;
  png.height = tex.height;
  uint32_t seed = 3;
  for (uint32_t i = 0; i < tex.width * tex.height; ++i) {
    seed = seed * 1664525u + 1013904223u;
    const uint32_t c = seed >> 8 & 0xffffff;
    tex.rgb.push_back(c);
    for (int k = 0; k < 3; ++k) png.rgb.push_back(static_cast<uint8_t>(c >> (8 * k)));
  }
  write_image(temp_path("strip_tex.png"), png);
  {
    std::ofstream mtl(temp_path("strip.mtl"));
    mtl << "newmtl painted\nKd 1 1 1\nmap_Kd strip_tex.png\n";
  }
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0.3f, 0, 1, 0.2f, 1, 1, 1, 0.5f, 0.5f, 0.9f, 0.1f, 0.9f, 0.6f};
  const std::vector<float> uv = {0, 0, 1.7f, 0.2f, 0.3f, 1.9f, 2.2f, 2.4f, 1.1f, 0.6f, -0.4f, 1.3f};
  const std::vector<uint32_t> idx = {0, 1, 2, 1, 3, 2, 0, 4, 3, 2, 5, 0};
  const std::string obj = temp_path("strip.obj");
  {
    std::ofstream f(obj);
    f << "mtllib strip.mtl\n";
    for (size_t v = 0; v < pos.size() / 3; ++v) f << "v " << pos[3 * v] << " " << pos[3 * v + 1] << " " << pos[3 * v + 2] << "\n";
    for (size_t v = 0; v < uv.size() / 2; ++v) f << "vt " << uv[2 * v] << " " << uv[2 * v + 1] << "\n";
    f << "usemtl painted\n";
    for (size_t t = 0; t < idx.size(); t += 3)
      f << "f " << idx[t] + 1 << "/" << idx[t] + 1 << " " << idx[t + 1] + 1 << "/" << idx[t + 1] + 1 << " "
        << idx[t + 2] + 1 << "/" << idx[t + 2] + 1 << "\n";
  }
  const std::string out = temp_path("strip.mvx");
  BuildOptions o;
  o.input = obj;
  o.output = out;
  o.resolution = 32;
  const BuildReport r = build_mvx(dev, o);
  ASSERT_EQ(r.attributes, "rgb");
  std::vector<float> tris, tri_uv;
  triangles_to_grid(r.grid, pos, idx.data(), idx.size() / 3, tris);
  for (uint32_t v : idx) tri_uv.insert(tri_uv.end(), {uv[2 * v], uv[2 * v + 1]});
  const ref::MeshVoxelColours want = ref::mesh_voxel_colours(tris, std::vector<uint32_t>(idx.size(), 0xffffff), 32,
                                                             std::vector<uint32_t>(idx.size() / 3, 0), tri_uv, {tex});
  const MvxFile f = read_mvx(out);
  ASSERT_EQ(decode_encoded(f.dag), want.keys);
  const std::vector<uint8_t> bytes = depth_first_bytes(want, 5);
  ASSERT_EQ(f.colours.size(), bytes.size());
  size_t differ = 0, distinct = 0;
  for (size_t i = 0; i < bytes.size(); ++i) differ += f.colours[i] != bytes[i];
  for (size_t i = 1; i < want.rgb.size(); ++i) distinct += want.rgb[i] != want.rgb[i - 1];
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(distinct, want.rgb.size() / 4);  // the texture shows, not one colour
}

TEST_P(MeshColourTest, RefusalsAreClearErrors) {
  Device& dev = shared_device(GetParam());
  const ColourMesh m = colour_sphere();
  const std::string coloured = write_colour_ply(m, "sphere_refuse.ply", false);
  const std::string plain = temp_path("sphere_plain.ply");
  write_ply(plain, m.pos, m.idx);
  const std::string out = temp_path("refused.mvx");
  EXPECT_EQ(build_mesh(dev, plain, out, Encoding::svdag, Attributes::automatic).attributes, "none");
  try {
    build_mesh(dev, plain, out, Encoding::svdag, Attributes::rgb);
    ADD_FAILURE() << "rgb on a mesh without colours";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no vertex colours or textures"), std::string::npos) << e.what();
  }
  EXPECT_EQ(build_mesh(dev, coloured, out, Encoding::svdag, Attributes::none, 32).attributes, "none");
}

// Out of core (cubes of 16 and 32 in a 64 grid) the colours and the DAG are the in-core build's, byte for byte.
TEST_P(MeshColourTest, OutOfCoreEqualsInCore) {
  Device& dev = shared_device(GetParam());
  const ColourMesh m = colour_sphere();
  const std::string in = write_colour_ply(m, "sphere_cubes.ply", false);
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag}) {
    SCOPED_TRACE(encoding_name(e));
    const std::string whole = temp_path("sphere_whole_" + encoding_name(e) + ".mvx");
    build_mesh(dev, in, whole, e, Attributes::automatic, 1024);
    const MvxFile want = read_mvx(whole);
    ASSERT_FALSE(want.colours.empty());
    for (uint32_t cube : {16u, 32u}) {
      const std::string part = temp_path("sphere_cubes_" + encoding_name(e) + std::to_string(cube) + ".mvx");
      const BuildReport r = build_mesh(dev, in, part, e, Attributes::automatic, cube);
      EXPECT_EQ(r.cube, cube);
      EXPECT_EQ(r.attributes, "rgb");
      const MvxFile got = read_mvx(part);
      EXPECT_TRUE(got.colours == want.colours) << "cube " << cube;
      EXPECT_EQ(got.dag.words, want.dag.words);
      EXPECT_EQ(got.dag.inner, want.dag.inner);
    }
  }
}

// Each voxel's best fragment, however its brick's fragments fall: a sphere of 2,048 triangles on grids of 8 to 64
// voxels puts up to hundreds of triangles in a brick (runs longer than a work-item takes whole, split between
// items) and a few in others; fed to the voxelizer in two halves (fragments sorted on the device) and in device
// batches of 100 triangles (every run combined by the atomic passes). Every third triangle samples a 7 x 5 texture
// (coordinates from its vertices' positions, past 1: it repeats), the others interpolate vertex colours. Always
// the reference's colours.
TEST_P(MeshColourTest, EveryRunOfFragmentsFollowsTheRule) {
  Device& dev = shared_device(GetParam());
  const ColourMesh m = colour_sphere(4);
  std::vector<uint32_t> tri_rgb, tri_tex;
  std::vector<float> tri_uv;
  for (uint32_t v : m.idx) {
    tri_rgb.push_back((m.rgb16[3 * v] >> 8) | (m.rgb16[3 * v + 1] >> 8) << 8 | (m.rgb16[3 * v + 2] >> 8) << 16);
    tri_uv.insert(tri_uv.end(), {m.pos[3 * v] * 2.5f + 0.3f, m.pos[3 * v + 1] * 1.5f - 0.2f});
  }
  for (size_t t = 0; t < m.idx.size() / 3; ++t) tri_tex.push_back(t % 3 == 0 ? 0 : io::kNoTexture);
  ref::RefTexture tex;
  tex.width = 7;
  tex.height = 5;
  for (uint32_t i = 0; i < 35; ++i) tex.rgb.push_back((i + 1) * 2654435761u >> 8);
  MeshTriangleColours colours;
  colours.rgb = tri_rgb;
  colours.texture = tri_tex;
  colours.uv = tri_uv;
  colours.textures.push_back({tex.width, tex.height, tex.rgb});
  for (uint32_t levels : {3u, 5u, 6u}) {
    const uint32_t n = 1u << levels;
    std::vector<float> tris;
    for (uint32_t v : m.idx)
      for (int k = 0; k < 3; ++k) tris.push_back((m.pos[3 * v + k] + 1.0f) * 0.4995f * float(n));
    const ref::MeshVoxelColours want_voxels = ref::mesh_voxel_colours(tris, tri_rgb, n, tri_tex, tri_uv, {tex});
    const std::vector<uint8_t> want = depth_first_bytes(want_voxels, levels);
    for (int halves : {1, 2})
      for (uint64_t batch : {uint64_t{0}, uint64_t{100}}) {
        SCOPED_TRACE("grid " + std::to_string(n) + ", halves " + std::to_string(halves) + ", batch " +
                     std::to_string(batch));
        Voxelizer v(dev, n);
        v.record_fragments();
        const size_t half = tris.size() / 9 / 2 * 9;
        if (halves == 1) {
          v.add(tris);
        } else {
          v.add(std::vector<float>(tris.begin(), tris.begin() + static_cast<std::ptrdiff_t>(half)));
          v.add(std::vector<float>(tris.begin() + static_cast<std::ptrdiff_t>(half), tris.end()));
        }
        const Bricks bricks = v.take_bricks();
        const Fragments fragments = v.take_fragments();
        EXPECT_EQ(fragments.sorted, halves == 1);
        EXPECT_EQ(fragments.size(), v.hits());
        ASSERT_EQ(keys_from_bricks(bricks), want_voxels.keys);
        const std::vector<uint8_t> got = mesh_voxel_colours(dev, bricks, fragments, tris, colours, levels, batch);
        ASSERT_EQ(got.size(), want.size());
        size_t differ = 0;
        for (size_t i = 0; i < want.size(); ++i) differ += got[i] != want[i];
        EXPECT_EQ(differ, 0u);
      }
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(MeshColourTest);

}  // namespace
}  // namespace mv::test

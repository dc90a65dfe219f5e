// Coloured point clouds through the whole build on every device: PLY and LAS in, .mvx out and back, PLY export.
// Geometry does not change with colour; points on voxel faces fall in the upper voxel (the top face in the last);
// 16-bit LAS colours keep their high byte unless every value fits 8 bits.
#include <nanovdb/util/IO.h>
#include <openvdb/openvdb.h>
#include <xxhash.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "colour_reference.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/interop.h"
#include "megavox/mvx.h"
#include "io/mvx_format.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test {
namespace {

void fs_copy(const std::string& from, const std::string& to) {
  std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing);
}

class ColourFilesTest : public ::testing::TestWithParam<DeviceInfo> {};

// Points on integer coordinates of an 8-unit cube, so with --resolution 8 --grid-origin min every point lies on
// voxel faces: (0, 0, 0) and (8, 8, 8) span the cube.
struct FaceCloud {
  std::vector<double> xyz;
  std::vector<uint32_t> rgb;
  std::vector<uint32_t> cells;  // what the rules say
};

FaceCloud face_cloud() {
  FaceCloud c;
  uint32_t seed = 7;
  auto next = [&] { return seed = seed * 1103515245u + 12345u; };
  for (int p = 0; p < 300; ++p) {
    double v[3];
    for (double& a : v) a = (next() >> 8) % 9;  // 0 .. 8
    if (p == 0) v[0] = v[1] = v[2] = 0;
    if (p == 1) v[0] = v[1] = v[2] = 8;
    c.xyz.insert(c.xyz.end(), v, v + 3);
    c.rgb.push_back((next() >> 4) & 0xffffff);
    for (double a : v) c.cells.push_back(a >= 8 ? 7u : static_cast<uint32_t>(a));
  }
  return c;
}

std::string face_cloud_ply(const FaceCloud& c, const std::string& name) {
  std::vector<points::PlyColumn> cols = {{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}},
                                         {"uchar", "red", {}}, {"uchar", "green", {}}, {"uchar", "blue", {}}};
  for (size_t p = 0; p < c.rgb.size(); ++p) {
    for (int a = 0; a < 3; ++a) cols[a].values.push_back(c.xyz[3 * p + a]);
    for (int k = 0; k < 3; ++k) cols[3 + k].values.push_back(c.rgb[p] >> (8 * k) & 255);
  }
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << points::make_cloud_ply(ply::Fmt::le, cols);
  return path;
}

BuildReport build_cloud_file(Device& dev, const std::string& in, const std::string& out, Encoding e, Attributes a) {
  BuildOptions o = points::cloud_build_options(in, out, 8, e);
  o.attributes = a;
  return build_mvx(dev, o);
}

// A binary little-endian PLY of double x, y, z (+ uchar r, g, b) as export writes it: centres and colours.
void read_voxel_ply(const std::string& path, std::vector<double>& xyz, std::vector<uint8_t>& rgb, bool& colour) {
  const std::vector<char> bytes = file_bytes(path);
  const std::string text(bytes.begin(), bytes.end());
  const size_t end = text.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = text.substr(0, end);
  colour = header.find("property uchar red") != std::string::npos;
  const size_t at = header.find("element vertex ");
  ASSERT_NE(at, std::string::npos);
  const size_t n = std::stoull(header.substr(at + 15));
  const size_t stride = colour ? 27 : 24;
  const char* body = bytes.data() + end + 11;
  ASSERT_EQ(bytes.size() - (end + 11), n * stride);
  xyz.resize(n * 3);
  rgb.clear();
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(&xyz[3 * i], body + i * stride, 24);
    if (colour) rgb.insert(rgb.end(), body + i * stride + 24, body + i * stride + 27);
  }
}

TEST_P(ColourFilesTest, PlyCloudBuildsRoundTripsAndExports) {
  Device& dev = shared_device(GetParam());
  const FaceCloud c = face_cloud();
  const std::string in = face_cloud_ply(c, "faces.ply");
  const std::vector<ref::ColourNode> want = ref::preorder_colours(c.cells, c.rgb, 3);
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag, Encoding::ussvdag, Encoding::svo}) {
    SCOPED_TRACE(encoding_name(e));
    const std::string out = temp_path("faces_" + encoding_name(e) + ".mvx");
    const std::string grey = temp_path("faces_grey_" + encoding_name(e) + ".mvx");
    const BuildReport r = build_cloud_file(dev, in, out, e, Attributes::automatic);
    const BuildReport g = build_cloud_file(dev, in, grey, e, Attributes::none);
    EXPECT_EQ(r.attributes, "rgb");
    EXPECT_EQ(g.attributes, "none");
    EXPECT_EQ(r.points, c.rgb.size());
    EXPECT_EQ(r.nodes_per_level, g.nodes_per_level);
    EXPECT_EQ(r.svo_nodes, g.svo_nodes);
    EXPECT_EQ(r.bytes, g.bytes);
    EXPECT_EQ(r.colour_entries, want.size());
    EXPECT_DOUBLE_EQ(r.colour_bits_per_voxel, 8.0 * double(32 + 3 * want.size()) / double(r.voxels));
    const MvxFile f = read_mvx(out);
    std::vector<uint8_t> bytes;
    for (const auto& n : want) bytes.insert(bytes.end(), n.rgb, n.rgb + 3);
    EXPECT_EQ(f.colours, bytes);
    EXPECT_TRUE(read_mvx(grey).colours.empty());
    EXPECT_EQ(decode_encoded(f.dag), ref::cloud_voxel_keys(c.cells));

    const std::string ply = temp_path("faces_" + encoding_name(e) + "_voxels.ply");
    ExportOptions x;
    x.input = out;
    x.output = ply;
    x.format = ExportFormat::ply;
    export_mvx(dev, x);
    std::vector<double> centres;
    std::vector<uint8_t> rgb;
    bool colour = false;
    read_voxel_ply(ply, centres, rgb, colour);
    EXPECT_TRUE(colour);
    std::vector<double> want_centres;
    std::vector<uint8_t> want_rgb;
    for (const auto& n : want) {
      if (n.level != 0) continue;
      for (int a = 0; a < 3; ++a) {
        uint32_t v = 0;
        for (int b = 0; b < 3; ++b) v |= uint32_t(n.code >> (3 * b + a) & 1) << b;
        want_centres.push_back(v + 0.5);
      }
      want_rgb.insert(want_rgb.end(), n.rgb, n.rgb + 3);
    }
    EXPECT_EQ(centres, want_centres);
    EXPECT_EQ(rgb, want_rgb);
    x.input = grey;
    x.output = temp_path("faces_grey_" + encoding_name(e) + "_voxels.ply");
    export_mvx(dev, x);
    read_voxel_ply(x.output, centres, rgb, colour);
    EXPECT_FALSE(colour);
    EXPECT_EQ(centres, want_centres);

    // OpenVDB and NanoVDB: a Vec3s grid 'colour' beside the mask, each voxel's colour / 255; SymVox drops them
    x.input = out;
    x.output = temp_path("faces_" + encoding_name(e) + ".vdb");
    x.format = ExportFormat::vdb;
    EXPECT_FALSE(export_mvx(dev, x).colours_dropped);
    openvdb::initialize();
    openvdb::io::File file(x.output);
    file.open();
    auto grid = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("colour"));
    file.close();
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->activeVoxelCount(), want_rgb.size() / 3);
    auto acc = grid->getConstAccessor();
    x.output = temp_path("faces_" + encoding_name(e) + ".nvdb");
    x.format = ExportFormat::nvdb;
    export_mvx(dev, x);
    auto handle = nanovdb::io::readGrid(x.output, "colour");
    const auto* nano = handle.grid<nanovdb::Vec3f>();
    ASSERT_NE(nano, nullptr);
    auto nacc = nano->getAccessor();
    size_t wrong = 0;
    for (size_t i = 0; i < want_rgb.size() / 3; ++i) {
      const openvdb::Coord c{int(want_centres[3 * i]), int(want_centres[3 * i + 1]), int(want_centres[3 * i + 2])};
      const openvdb::Vec3s v = acc.getValue(c);
      const nanovdb::Vec3f nv = nacc.getValue(nanovdb::Coord(c.x(), c.y(), c.z()));
      for (int k = 0; k < 3; ++k)
        wrong += v[k] != want_rgb[3 * i + k] / 255.0f || nv[k] != want_rgb[3 * i + k] / 255.0f || !acc.isValueOn(c);
    }
    EXPECT_EQ(wrong, 0u);
    x.output = temp_path("faces_" + encoding_name(e) + ".svdag");
    x.format = ExportFormat::symvox_svdag;
    EXPECT_TRUE(export_mvx(dev, x).colours_dropped);
  }
}

// LAS colours are 16-bit: their high byte, unless every value of the file fits 8 bits.
TEST_P(ColourFilesTest, LasColoursUseTheHighByteUnlessAllFitEightBits) {
  Device& dev = shared_device(GetParam());
  points::LasSpec spec;
  spec.scale[0] = spec.scale[1] = spec.scale[2] = 1;
  spec.offset[0] = spec.offset[1] = spec.offset[2] = 0;
  for (bool wide : {false, true}) {
    std::vector<points::LasPoint> pts(3);
    const int32_t xyz[3][3] = {{0, 0, 0}, {8, 8, 8}, {1, 0, 0}};
    const uint16_t rgb[3][3] = {{10, 200, 255}, {0, 1, 2}, {12, 100, 255}};
    for (int p = 0; p < 3; ++p)
      for (int a = 0; a < 3; ++a) {
        pts[p].xyz[a] = xyz[p][a];
        pts[p].rgb[a] = static_cast<uint16_t>(wide ? rgb[p][a] * 257 : rgb[p][a]);
      }
    const std::string in = temp_path(wide ? "wide.las" : "narrow.las");
    std::ofstream(in, std::ios::binary) << points::make_las(spec, pts);
    const std::string out = temp_path(wide ? "wide.mvx" : "narrow.mvx");
    build_cloud_file(dev, in, out, Encoding::svdag, Attributes::rgb);
    const std::vector<uint32_t> cells = {0, 0, 0, 7, 7, 7, 1, 0, 0};
    std::vector<uint32_t> packed;
    for (auto& c : rgb) packed.push_back(c[0] | c[1] << 8 | c[2] << 16);
    std::vector<uint8_t> bytes;
    for (const auto& n : ref::preorder_colours(cells, packed, 3)) bytes.insert(bytes.end(), n.rgb, n.rgb + 3);
    EXPECT_EQ(read_mvx(out).colours, bytes) << (wide ? "16-bit" : "8-bit");
  }
}

// An explicit cube (--bounds) keeps the points inside it, its top faces included, and drops the rest.
TEST_P(ColourFilesTest, BoundsKeepThePointsInside) {
  Device& dev = shared_device(GetParam());
  const FaceCloud c = face_cloud();
  const std::string in = face_cloud_ply(c, "bounded.ply");
  BuildOptions o;
  o.input = in;
  o.output = temp_path("bounded.mvx");
  o.resolution = 8;
  o.placement = parse_grid_bounds("0,0,0,4");
  const BuildReport r = build_mvx(dev, o);
  std::vector<uint32_t> cells, rgb;
  for (size_t p = 0; p < c.rgb.size(); ++p) {
    const double* v = &c.xyz[3 * p];
    if (v[0] > 4 || v[1] > 4 || v[2] > 4) continue;
    for (int a = 0; a < 3; ++a) cells.push_back(std::min(7u, static_cast<uint32_t>(2 * v[a])));
    rgb.push_back(c.rgb[p]);
  }
  EXPECT_EQ(r.points, rgb.size());
  const MvxFile f = read_mvx(o.output);
  EXPECT_EQ(decode_encoded(f.dag), ref::cloud_voxel_keys(cells));
  std::vector<uint8_t> bytes;
  for (const auto& n : ref::preorder_colours(cells, rgb, 3)) bytes.insert(bytes.end(), n.rgb, n.rgb + 3);
  EXPECT_EQ(f.colours, bytes);
}

// --attributes rgb on a cloud without colour is an error; a PLY with faces stays a mesh.
TEST_P(ColourFilesTest, RgbWithoutColourIsAnError) {
  Device& dev = shared_device(GetParam());
  const std::string in = temp_path("nocolour.ply");
  std::ofstream(in, std::ios::binary) << points::make_cloud_ply(
      ply::Fmt::ascii, {{"float", "x", {0, 1}}, {"float", "y", {0, 1}}, {"float", "z", {0, 1}}});
  EXPECT_THROW(build_cloud_file(dev, in, temp_path("nocolour.mvx"), Encoding::svdag, Attributes::rgb), Error);
  const BuildReport r = build_cloud_file(dev, in, temp_path("nocolour.mvx"), Encoding::svdag, Attributes::automatic);
  EXPECT_EQ(r.voxels, 2u);
  EXPECT_EQ(r.attributes, "none");
}

// A paged version 3 file is a version 4 one without colours: it still opens. Colours in a version 3 file, and a
// colour section whose head or size disagrees with the counts, are damage with a clear message.
TEST_P(ColourFilesTest, OlderVersionsOpenAndDamagedColoursAreClearErrors) {
  Device& dev = shared_device(GetParam());
  const FaceCloud c = face_cloud();
  const std::string in = face_cloud_ply(c, "versions.ply");
  const std::string grey = temp_path("versions_grey.mvx"), coloured = temp_path("versions.mvx");
  build_cloud_file(dev, in, grey, Encoding::svdag, Attributes::none);
  build_cloud_file(dev, in, coloured, Encoding::svdag, Attributes::rgb);
  auto patch = [](const std::string& path, const std::function<void(mvx_format::Header&, std::vector<char>&)>& f) {
    std::vector<char> b = file_bytes(path);
    mvx_format::Header h;
    std::memcpy(&h, b.data(), sizeof h);
    f(h, b);
    h.checksum = XXH3_64bits(&h, offsetof(mvx_format::Header, checksum));
    std::memcpy(b.data(), &h, sizeof h);
    write_bytes(path, b);
  };
  const MvxFile want = read_mvx(grey);
  patch(grey, [](mvx_format::Header& h, std::vector<char>&) { h.version = 3; });
  EXPECT_EQ(read_mvx(grey).dag.words, want.dag.words);
  const std::string damaged = temp_path("versions_damaged.mvx");
  fs_copy(coloured, damaged);
  patch(damaged, [](mvx_format::Header& h, std::vector<char>&) { h.version = 3; });
  EXPECT_NE(error_message([&] { read_mvx(damaged); }).find("colours in a version 3"), std::string::npos);
  // One colour fewer than the nodes: the head's count is checked against the counts section.
  fs_copy(coloured, damaged);
  patch(damaged, [](mvx_format::Header& h, std::vector<char>& b) {
    for (uint32_t i = 0; i < h.sections; ++i)
      if (h.table[i].kind == mvx_format::kColours) {
        mvx_format::ColourHead head;
        std::memcpy(&head, b.data() + h.table[i].offset, sizeof head);
        head.entries -= 1;
        std::memcpy(b.data() + h.table[i].offset, &head, sizeof head);
        h.table[i].checksum = XXH3_64bits(b.data() + h.table[i].offset, h.table[i].bytes);
      }
  });
  EXPECT_NE(error_message([&] { read_mvx(damaged); }).find("octree nodes"), std::string::npos);
  // A flipped colour byte: the section's checksum.
  fs_copy(coloured, damaged);
  patch(damaged, [](mvx_format::Header& h, std::vector<char>& b) {
    for (uint32_t i = 0; i < h.sections; ++i)
      if (h.table[i].kind == mvx_format::kColours) b[h.table[i].offset + 40] ^= 1;
  });
  EXPECT_NE(error_message([&] { read_mvx(damaged); }).find("checksum mismatch in the colours"), std::string::npos);
}

MV_INSTANTIATE_ON_ALL_DEVICES(ColourFilesTest);

}  // namespace
}  // namespace mv::test

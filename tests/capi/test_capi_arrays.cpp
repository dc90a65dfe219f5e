// The C API's calls on caller memory, on every device, against their file twins: device listing, coloured mesh
// arrays against a coloured PLY, point arrays against a PLY of the same values, a point hierarchy read back
// against read_mvx_points, masks and mask models from pixels against the same pixels in a file; and each
// call's refusals.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "io/image_reader.h"
#include "io/mvm_file.h"
#include "megavox/megavox.h"
#include "megavox/mvx.h"
#include "capi_fixture.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test::capi {
namespace {

class CApiArraysTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST(CApiDevices, TheListIsTheRuntimesWithOneDefault) {
  const std::vector<DeviceInfo> all = list_devices();
  ASSERT_EQ(mvListDevices(nullptr, 0), all.size());
  std::vector<MvDeviceDescription> d(all.size() + 1);
  ASSERT_EQ(mvListDevices(d.data(), d.size()), all.size());
  int defaults = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(d[i].selector, all[i].selector());
    EXPECT_EQ(d[i].backend, all[i].backend);
    EXPECT_EQ(d[i].type, all[i].type);
    EXPECT_EQ(d[i].memoryBytes, all[i].global_memory_bytes);
    defaults += d[i].isDefault;
    if (d[i].isDefault) {
      EXPECT_EQ(d[i].selector, select_device("").selector());
    }
  }
  EXPECT_EQ(defaults, all.empty() ? 0 : 1);
  if (!all.empty()) {  // a short buffer gets the first ones, and the count
    MvDeviceDescription one{};
    EXPECT_EQ(mvListDevices(&one, 1), all.size());
    EXPECT_STREQ(one.selector, d[0].selector);
  }
  EXPECT_EQ(mvListDevices(nullptr, 3), 0u);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT);
}

TEST_P(CApiArraysTest, ColouredMeshArraysBuildWhatAColouredPlyBuilds) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  const uint8_t rgb[6 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 250, 200, 10, 7, 99, 180, 128, 128, 128};
  const std::string ply = temp_path("octa_rgb.ply"), a = temp_path("octa_rgb_mem.mvx"), b = temp_path("octa_rgb_file.mvx");
  {
    std::ofstream out(ply);
    out << "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 8\n"
           "property list uchar uint vertex_indices\nend_header\n";
    for (int v = 0; v < 6; ++v)
      out << m.positions[3 * v] << " " << m.positions[3 * v + 1] << " " << m.positions[3 * v + 2] << " "
          << int(rgb[3 * v]) << " " << int(rgb[3 * v + 1]) << " " << int(rgb[3 * v + 2]) << "\n";
    for (int t = 0; t < 8; ++t) out << "3 " << m.indices[3 * t] << " " << m.indices[3 * t + 1] << " " << m.indices[3 * t + 2] << "\n";
  }
  MvBuildArguments args;
  mvInitBuildArguments(&args);
  args.resolution = 32;
  args.output = a.c_str();
  MvScene s1 = mvBuildSceneFromMemoryRgb(dev.handle, m.positions.data(), 6, m.indices.data(), 8, rgb, &args);
  ASSERT_TRUE(s1) << mvGetDeviceLastErrorMessage(dev.handle);
  args.output = b.c_str();
  MvScene s2 = mvBuildSceneFromFile(dev.handle, ply.c_str(), &args);
  ASSERT_TRUE(s2) << mvGetDeviceLastErrorMessage(dev.handle);
  EXPECT_EQ(file_bytes(a), file_bytes(b));
  uint64_t entries = 0;
  ASSERT_EQ(mvGetSceneColourEntries(s1, &entries), MV_ERROR_NONE);
  EXPECT_GT(entries, 0u);
  mvReleaseScene(s1);
  mvReleaseScene(s2);
  // NULL colours: the colourless build of mvBuildSceneFromMemory
  MvScene s3 = mvBuildSceneFromMemoryRgb(dev.handle, m.positions.data(), 6, m.indices.data(), 8, nullptr, &args);
  ASSERT_TRUE(s3);
  ASSERT_EQ(mvGetSceneColourEntries(s3, &entries), MV_ERROR_NONE);
  EXPECT_EQ(entries, 0u);
  mvReleaseScene(s3);
}

// A float32 helix with colours, intensities and one extra byte per point.
struct HelixArrays {
  std::vector<float> xyz;
  std::vector<uint16_t> rgb, intensity;
  std::vector<uint8_t> extra;
};
HelixArrays helix(int n) {
  HelixArrays h;
  for (int i = 0; i < n; ++i) {
    h.xyz.insert(h.xyz.end(), {float(3 * std::cos(0.01 * i)), float(2 * std::sin(0.013 * i)), float(0.002 * i)});
    h.rgb.insert(h.rgb.end(), {uint16_t(i % 256), uint16_t((7 * i) % 256), uint16_t((13 * i) % 256)});
    h.intensity.push_back(uint16_t(i * 31));
    h.extra.push_back(uint8_t(i % 7));
  }
  return h;
}

TEST_P(CApiArraysTest, PointArraysBuildWhatAPlyOfTheSameValuesBuilds) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const int n = 5000;
  const HelixArrays h = helix(n);
  std::vector<points::PlyColumn> columns = {{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}},
                                    {"uchar", "red", {}}, {"uchar", "green", {}}, {"uchar", "blue", {}},
                                    {"ushort", "intensity", {}}};
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) columns[k].values.push_back(h.xyz[3 * i + k]);
    for (int k = 0; k < 3; ++k) columns[3 + k].values.push_back(h.rgb[3 * i + k]);
    columns[6].values.push_back(h.intensity[i]);
  }
  const std::string ply = ply::write_file("helix_arrays.ply", points::make_cloud_ply(ply::Fmt::le, columns));
  const std::string a = temp_path("helix_mem.mvx"), b = temp_path("helix_file.mvx");
  MvPointArrays p;
  mvInitPointArrays(&p);
  p.count = n;
  p.xyz32 = h.xyz.data();
  p.rgb = h.rgb.data();
  p.intensity = h.intensity.data();
  ASSERT_EQ(mvBuildPointsFromMemory(dev.handle, &p, a.c_str(), nullptr), MV_ERROR_NONE) << mvGetDeviceLastErrorMessage(dev.handle);
  ASSERT_EQ(mvBuildPointsFile(dev.handle, ply.c_str(), b.c_str(), nullptr), MV_ERROR_NONE);
  const PointHierarchy x = read_mvx_points(a), y = read_mvx_points(b);
  EXPECT_EQ(x.source.format, "float32 arrays");
  ASSERT_EQ(x.nodes.size(), y.nodes.size());
  EXPECT_EQ(0, std::memcmp(x.nodes.data(), y.nodes.data(), x.nodes.size() * sizeof(PointNode)));
  EXPECT_EQ(x.points.xyz, y.points.xyz);
  EXPECT_EQ(x.points.rgb, y.points.rgb);
  EXPECT_EQ(x.points.intensity, y.points.intensity);
  EXPECT_EQ(x.source.scale[0], y.source.scale[0]);

  // Read back through the C API: the nodes as stored, positions in world units, every column.
  p.extra = h.extra.data();
  p.extraBytes = 1;
  ASSERT_EQ(mvBuildPointsFromMemory(dev.handle, &p, a.c_str(), nullptr), MV_ERROR_NONE);
  const PointHierarchy z = read_mvx_points(a);
  MvPoints r = mvOpenPoints(dev.handle, a.c_str());
  ASSERT_TRUE(r) << mvGetDeviceLastErrorMessage(dev.handle);
  MvPointsInfo info;
  ASSERT_EQ(mvGetPointsInfo(r, &info), MV_ERROR_NONE);
  EXPECT_EQ(info.nodes, z.nodes.size());
  EXPECT_EQ(info.points, z.points.size());
  EXPECT_EQ(info.pointsIn, uint64_t(n));
  EXPECT_EQ(info.attributes, MV_POINT_RGB | MV_POINT_INTENSITY | MV_POINT_EXTRA);
  EXPECT_EQ(info.extraBytes, 1u);
  std::vector<MvPointNode> nodes(info.nodes);
  ASSERT_EQ(mvGetPointNodes(r, 0, info.nodes, nodes.data()), MV_ERROR_NONE);
  EXPECT_EQ(0, std::memcmp(nodes.data(), z.nodes.data(), nodes.size() * sizeof(MvPointNode)));
  const uint64_t np = info.points;
  std::vector<double> xyz(3 * np);
  std::vector<uint16_t> rgb(3 * np), intensity(np);
  std::vector<uint8_t> extra(np);
  ASSERT_EQ(mvGetPointData(r, 0, np, xyz.data(), rgb.data(), intensity.data(), extra.data(), nullptr), MV_ERROR_NONE);
  EXPECT_EQ(rgb, z.points.rgb);
  EXPECT_EQ(intensity, z.points.intensity);
  EXPECT_EQ(extra, z.points.extra);
  for (uint64_t i = 0; i < 3 * np; i += 97) EXPECT_EQ(xyz[i], z.source.scale[i % 3] * z.points.xyz[i]);
  // every point at the leaves, within half a grid step of where it was given
  uint64_t at_leaves = 0;
  for (const PointNode& node : z.nodes)
    if (node.leaf()) at_leaves += node.point_count;
  EXPECT_EQ(at_leaves, uint64_t(n));
  EXPECT_LE(std::fabs(xyz[0] - std::round(xyz[0] / z.source.scale[0]) * z.source.scale[0]), 0.0);

  // refusals: a range past the end, a column the hierarchy lacks
  EXPECT_EQ(mvGetPointNodes(r, info.nodes, 1, nodes.data()), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvGetPointData(r, np - 1, 2, xyz.data(), nullptr, nullptr, nullptr, nullptr), MV_ERROR_INVALID_ARGUMENT);
  mvReleasePoints(r);
  p.rgb = nullptr;
  p.intensity = nullptr;
  p.extra = nullptr;
  ASSERT_EQ(mvBuildPointsFromMemory(dev.handle, &p, a.c_str(), nullptr), MV_ERROR_NONE);
  r = mvOpenPoints(dev.handle, a.c_str());
  ASSERT_TRUE(r);
  EXPECT_EQ(mvGetPointData(r, 0, 1, xyz.data(), rgb.data(), nullptr, nullptr, nullptr), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mvGetDeviceLastErrorMessage(dev.handle)).find("no colours"), std::string::npos);
  mvReleasePoints(r);
}

TEST_P(CApiArraysTest, PointArraysAreCheckedBeforeAnyWork) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string out = temp_path("refused_points.mvx");
  std::filesystem::remove(out);
  std::vector<double> xyz = {0, 0, 0, 1, 2, 3, NAN, 0, 0};
  MvPointArrays p;
  mvInitPointArrays(&p);
  p.count = 3;
  p.xyz64 = xyz.data();
  EXPECT_EQ(mvBuildPointsFromMemory(dev.handle, &p, out.c_str(), nullptr), MV_ERROR_INPUT);
  EXPECT_NE(std::string(mvGetDeviceLastErrorMessage(dev.handle)).find("point 2"), std::string::npos);
  std::vector<float> xyz32 = {0, 0, 0};
  p.xyz32 = xyz32.data();  // both kinds of position
  EXPECT_EQ(mvBuildPointsFromMemory(dev.handle, &p, out.c_str(), nullptr), MV_ERROR_INVALID_ARGUMENT);
  p.byteSize = 8;
  EXPECT_EQ(mvBuildPointsFromMemory(dev.handle, &p, out.c_str(), nullptr), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvBuildPointsFromMemory(dev.handle, nullptr, out.c_str(), nullptr), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(mvOpenPoints(dev.handle, temp_path("no_such_points.mvx").c_str()), nullptr);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_IO);
}

TEST_P(CApiArraysTest, AHierarchyGivesBackItsWholeCrs) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  points::LasSpec spec;
  spec.wkt = "PROJCS[\"NAD83 / Oregon GIC Lambert (ft)\"," + std::string(3000, 'x') + "]";  // past any fixed field
  const std::string las = ply::write_file("crs_arrays.las", points::make_las(spec, points::las_points(300, 0, 5)));
  const std::string out = temp_path("crs_arrays.mvx");
  ASSERT_EQ(mvBuildPointsFile(dev.handle, las.c_str(), out.c_str(), nullptr), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  MvPoints h = mvOpenPoints(dev.handle, out.c_str());
  ASSERT_TRUE(h);
  const size_t n = mvGetPointsCrs(h, nullptr, 0);
  ASSERT_EQ(n, spec.wkt.size());
  std::string text(n, '?');
  EXPECT_EQ(mvGetPointsCrs(h, text.data(), n + 1), n);
  EXPECT_EQ(text, spec.wkt);
  char small[8];
  EXPECT_EQ(mvGetPointsCrs(h, small, sizeof small), n);
  EXPECT_STREQ(small, spec.wkt.substr(0, 7).c_str());
  MvPointsInfo info;
  ASSERT_EQ(mvGetPointsInfo(h, &info), MV_ERROR_NONE);
  EXPECT_EQ(std::string(info.format).rfind("LAS 1.2", 0), 0u) << info.format;

  // The LAS fields by name, each inside the extra bytes, and each point's classification where it says.
  const size_t nf = mvGetPointFields(h, nullptr, 0);
  ASSERT_EQ(nf, 11u);  // format 3: ten fields and the GPS time
  std::vector<MvPointField> fields(nf);
  EXPECT_EQ(mvGetPointFields(h, fields.data(), nf), nf);
  EXPECT_STREQ(fields[2].name, "classification");
  EXPECT_EQ(fields[2].type, MV_FIELD_U8);
  EXPECT_STREQ(fields[10].name, "gps_time");
  EXPECT_EQ(fields[10].type, MV_FIELD_F64);
  EXPECT_EQ(fields[10].offset + 8, info.extraBytes);
  MvPointField one;
  EXPECT_EQ(mvGetPointFields(h, &one, 1), nf);
  EXPECT_STREQ(one.name, "return_number");
  mvReleasePoints(h);
}

// A 48 x 32 RGB image: a dark, slightly noisy background and a bright square at (16, 8) of side 16.
std::vector<uint8_t> square_pixels() {
  std::vector<uint8_t> px;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      const bool in = x >= 16 && x < 32 && y >= 8 && y < 24;
      const auto v = static_cast<uint8_t>(in ? 220 + (x * 7 + y) % 20 : 20 + (x * 3 + y * 5) % 20);
      px.insert(px.end(), {v, uint8_t(in ? v : v / 2), uint8_t(in ? v / 2 : v)});
    }
  return px;
}

TEST_P(CApiArraysTest, MasksFromPixelsEqualMasksFromTheSameFile) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::vector<uint8_t> px = square_pixels();
  const std::string ppm = temp_path("square_arrays.ppm"), png = temp_path("square_arrays_mask.png");
  {
    std::ofstream out(ppm, std::ios::binary);
    out << "P6\n48 32\n255\n";
    out.write(reinterpret_cast<const char*>(px.data()), std::streamsize(px.size()));
  }
  MvMaskArguments args;
  mvInitMaskArguments(&args);
  args.hasRect = true;
  const uint32_t rect[4] = {12, 4, 24, 24};
  std::memcpy(args.rect, rect, sizeof rect);
  ASSERT_EQ(mvMaskImageFile(dev.handle, ppm.c_str(), png.c_str(), &args), MV_ERROR_NONE);
  const RasterImage from_file = io::read_image(png);
  // the same pixels in memory, rows padded to show the stride is honoured
  const size_t stride = 48 * 3 + 5;
  std::vector<uint8_t> padded(32 * stride, 77);
  for (int y = 0; y < 32; ++y) std::memcpy(padded.data() + y * stride, px.data() + y * 48 * 3, 48 * 3);
  MvImageView view{padded.data(), 48, 32, 3, 1, stride};
  std::vector<uint8_t> mask(48 * 32);
  ASSERT_EQ(mvMaskImage(dev.handle, &view, nullptr, &args, mask.data()), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  ASSERT_EQ(from_file.samples.size(), mask.size());
  EXPECT_TRUE(std::equal(mask.begin(), mask.end(), from_file.samples.begin()));
  EXPECT_EQ(mask[20 * 48 + 24], 255);
  EXPECT_EQ(mask[0], 0);

  // a seed map in memory alone: sure foreground inside the square, sure background on the border
  std::vector<uint8_t> seeds(48 * 32, 128);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      if (x < 2 || y < 2 || x >= 46 || y >= 30) seeds[y * 48 + x] = 0;
      if (x >= 20 && x < 28 && y >= 12 && y < 20) seeds[y * 48 + x] = 255;
    }
  MvMaskArguments only_seeds;
  mvInitMaskArguments(&only_seeds);
  ASSERT_EQ(mvMaskImage(dev.handle, &view, seeds.data(), &only_seeds, mask.data()), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  EXPECT_EQ(mask[16 * 48 + 24], 255);
  EXPECT_EQ(mask[0], 0);
  seeds[5] = 100;  // none of the five labels
  EXPECT_EQ(mvMaskImage(dev.handle, &view, seeds.data(), &only_seeds, mask.data()), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvMaskImage(dev.handle, &view, nullptr, &only_seeds, mask.data()), MV_ERROR_INVALID_ARGUMENT);  // no start
  MvImageView two{padded.data(), 48, 32, 2, 1, 0};
  EXPECT_EQ(mvMaskImage(dev.handle, &two, nullptr, &args, mask.data()), MV_ERROR_INVALID_ARGUMENT);

  // a model trained on the pixels and their mask writes what MaskModel::train makes of the file's
  const std::string mvm = temp_path("square_arrays.mvm");
  const uint8_t* masks[] = {mask.data()};
  ASSERT_EQ(mvMaskImage(dev.handle, &view, nullptr, &args, mask.data()), MV_ERROR_NONE);
  ASSERT_EQ(mvTrainMaskModel(dev.handle, &view, masks, 1, mvm.c_str()), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  MaskModel expected = MaskModel::empty(3);
  expected.train(io::read_image(ppm), from_file.samples, 48, 32);
  const MaskModel got = io::read_mvm(mvm);
  EXPECT_EQ(got.fg, expected.fg);
  EXPECT_EQ(got.bg, expected.bg);
  const std::vector<uint8_t> all_fg(48 * 32, 255);
  const uint8_t* only_fg[] = {all_fg.data()};
  EXPECT_EQ(mvTrainMaskModel(dev.handle, &view, only_fg, 1, mvm.c_str()), MV_ERROR_INPUT);  // no background pixel
}

MV_INSTANTIATE_ON_ALL_DEVICES(CApiArraysTest);

}  // namespace
}  // namespace mv::test::capi

// The C API's file work on every device: point-cloud builds (.mvx and 3D Tiles, as a call and as a job) against
// the C++ builder, masks against mask_image, pictures written and read back, preset view cameras; and each of
// their failures with its code.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "io/image_reader.h"
#include "megavox/mask.h"
#include "megavox/megavox.hpp"
#include "megavox/point_build.h"
#include "megavox/render.h"
#include "capi_fixture.h"
#include "test_support.h"

namespace mv::test::capi {
namespace {

namespace fs = std::filesystem;

class CApiFilesTest : public ::testing::TestWithParam<DeviceInfo> {};

// An ASCII PLY cloud of n points on a helix (distinct, spread over a cube).
std::string helix_cloud(const std::string& name, int n) {
  const std::string path = temp_path(name);
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (int i = 0; i < n; ++i) out << std::cos(0.05 * i) << " " << std::sin(0.05 * i) << " " << 0.001 * i << "\n";
  return path;
}

// A 48 x 32 binary PPM: a dark, slightly noisy background and a bright square at (16, 8) of side 16.
std::string square_photo(const std::string& name) {
  const std::string path = temp_path(name);
  std::ofstream out(path, std::ios::binary);
  out << "P6\n48 32\n255\n";
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      const bool in = x >= 16 && x < 32 && y >= 8 && y < 24;
      const unsigned char v = static_cast<unsigned char>(in ? 220 + (x * 7 + y) % 20 : 20 + (x * 3 + y * 5) % 20);
      out.put(static_cast<char>(v)).put(static_cast<char>(in ? v : v / 2)).put(static_cast<char>(in ? v / 2 : v));
    }
  return path;
}

MvError last_error(MvDevice d, std::string* message = nullptr) {
  if (message) *message = mvGetDeviceLastErrorMessage(d);
  return mvGetDeviceError(d);
}

bool refuse_at_build(void* user, const char* stage, double) {
  static_cast<std::vector<std::string>*>(user)->push_back(stage);
  return std::strcmp(stage, "build") != 0;
}

TEST_P(CApiFilesTest, PointBuildsWriteTheCppBuildersFiles) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string cloud = helix_cloud("capi_helix.ply", 3000);
  const std::string from_c = temp_path("capi_points.mvx"), from_cpp = temp_path("cpp_points.mvx");
  MvPointBuildArguments a;
  mvInitPointBuildArguments(&a);
  a.maxNodePoints = 500;
  ASSERT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), from_c.c_str(), &a), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  PointFileOptions o;
  o.input = cloud;
  o.output = from_cpp;
  o.build.max_node_points = 500;
  build_points_file(shared_device(GetParam()), o);
  EXPECT_EQ(file_bytes(from_c), file_bytes(from_cpp));

  // 3D Tiles, as a job: done, its fraction whole, no scene to take
  const std::string tiles = temp_path("capi_tiles");
  fs::remove_all(tiles);
  a.format = "3dtiles";
  MvJob job = mvBuildPointsFileAsync(dev.handle, cloud.c_str(), tiles.c_str(), &a);
  ASSERT_TRUE(job);
  EXPECT_EQ(mvWaitJob(job), MV_ERROR_NONE) << mvGetJobMessage(job);
  double fraction = 0;
  EXPECT_EQ(mvGetJobStatus(job, &fraction), MV_JOB_DONE);
  EXPECT_EQ(fraction, 1.0);
  EXPECT_EQ(mvGetJobScene(job), nullptr);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_INVALID_OPERATION);
  mvReleaseJob(job);
  EXPECT_TRUE(fs::is_regular_file(fs::path(tiles) / "tileset.json"));

  // a progress function that says stop: cancelled, nothing written
  std::vector<std::string> stages;
  a.format = "mvx";
  a.progress = refuse_at_build;
  a.progressUserPtr = &stages;
  const std::string stopped = temp_path("capi_stopped.mvx");
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), stopped.c_str(), &a), MV_ERROR_CANCELLED);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_CANCELLED);
  ASSERT_FALSE(stages.empty());
  EXPECT_EQ(stages.front(), "read");
  EXPECT_FALSE(fs::exists(stopped));
  fs::remove_all(tiles);
}

TEST_P(CApiFilesTest, PointBuildFailuresComeWithTheirCodes) {
  const std::string cloud = helix_cloud("capi_helix_err.ply", 2000), out = temp_path("capi_err.mvx");
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  MvPointBuildArguments a;
  mvInitPointBuildArguments(&a);
  std::string m;
  a.format = "las";  // not an output format
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), out.c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(last_error(dev.handle, &m), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(m.find("choose mvx or 3dtiles"), std::string::npos) << m;
  mvInitPointBuildArguments(&a);
  a.byteSize = 4;
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), out.c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  // A caller built against the struct before its tiles' options still builds, with their defaults.
  mvInitPointBuildArguments(&a);
  a.byteSize = offsetof(MvPointBuildArguments, tilesVersion);
  a.tilesVersion = "2.0";  // not read: past the caller's struct
  const std::string older = temp_path("capi_older_args.mvx");
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), older.c_str(), &a), MV_ERROR_NONE) << last_error(dev.handle, &m);
  fs::remove(older);
  mvInitPointBuildArguments(&a);
  a.format = "3dtiles";
  a.tilesVersion = "2.0";
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), temp_path("capi_tiles2").c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  mvInitPointBuildArguments(&a);
  const double inverted[6] = {1, 0, 0, 0, 1, 1};
  a.bounds = inverted;
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), out.c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  mvInitPointBuildArguments(&a);
  a.format = "3dtiles";
  a.crs = "EPSG:999999";
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), temp_path("capi_tiles_crs").c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(last_error(dev.handle, &m), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(m.find("EPSG:999999"), std::string::npos) << m;
  EXPECT_FALSE(fs::exists(temp_path("capi_tiles_crs")));
  mvInitPointBuildArguments(&a);
  EXPECT_EQ(mvBuildPointsFile(dev.handle, "/no/such/cloud.ply", out.c_str(), &a), MV_ERROR_IO);  // cannot open
  EXPECT_EQ(mvBuildPointsFile(dev.handle, cloud.c_str(), "/no/such/folder/x.mvx", &a), MV_ERROR_IO);
  const std::string garbage = temp_path("capi_garbage.ply");
  std::ofstream(garbage) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2\n";
  EXPECT_EQ(mvBuildPointsFile(dev.handle, garbage.c_str(), out.c_str(), &a), MV_ERROR_INPUT);  // malformed
  MvJob failed = mvBuildPointsFileAsync(dev.handle, garbage.c_str(), out.c_str(), &a);
  ASSERT_TRUE(failed);
  EXPECT_EQ(mvWaitJob(failed), MV_ERROR_INPUT);
  EXPECT_EQ(mvGetJobStatus(failed, nullptr), MV_JOB_FAILED);
  mvReleaseJob(failed);
  // a host memory budget that not even the out-of-core build fits
  CDevice tight(GetParam(), "host_memory=1K");
  ASSERT_TRUE(tight.handle);
  EXPECT_EQ(mvBuildPointsFile(tight.handle, cloud.c_str(), out.c_str(), &a), MV_ERROR_OUT_OF_MEMORY);
  EXPECT_EQ(last_error(tight.handle, &m), MV_ERROR_OUT_OF_MEMORY);
  EXPECT_NE(m.find("host memory budget"), std::string::npos) << m;
  EXPECT_EQ(m.find("--"), std::string::npos) << m;  // the library's terms, not the CLI's flags
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(mvBuildPointsFile(nullptr, cloud.c_str(), out.c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT);
  // the RAII layer: the same codes as exceptions
  megavox::Device cpp("device=" + GetParam().selector());
  try {
    cpp.build_points("/no/such/cloud.ply", out);
    ADD_FAILURE() << "no exception";
  } catch (const megavox::Error& e) {
    EXPECT_EQ(e.code(), MV_ERROR_IO) << e.what();
  }
  try {
    cpp.build_points_async(garbage, out).finish();
    ADD_FAILURE() << "no exception";
  } catch (const megavox::Error& e) {
    EXPECT_EQ(e.code(), MV_ERROR_INPUT) << e.what();
  }
}

TEST_P(CApiFilesTest, MasksWriteMaskImagesBytes) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string photo = square_photo("capi_square.ppm"), out = temp_path("capi_mask.png");
  MvMaskArguments a;
  mvInitMaskArguments(&a);
  a.hasRect = true;
  const uint32_t rect[4] = {12, 4, 24, 24};
  std::memcpy(a.rect, rect, sizeof rect);
  ASSERT_EQ(mvMaskImageFile(dev.handle, photo.c_str(), out.c_str(), &a), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  const RasterImage got = io::read_image(out);
  ASSERT_EQ(got.width, 48u);
  ASSERT_EQ(got.height, 32u);
  MaskStart start;
  start.box = MaskBox{12, 4, 24, 24};
  const MaskResult want = mask_image(shared_device(GetParam()), io::read_image(photo), start);
  ASSERT_EQ(got.samples.size(), want.mask.size());
  EXPECT_TRUE(std::equal(want.mask.begin(), want.mask.end(), got.samples.begin()));
  EXPECT_EQ(got.samples[16 * 48 + 24], 255);  // the square's middle
  EXPECT_EQ(got.samples[0], 0);

  // as a job, the same bytes
  const std::string job_out = temp_path("capi_mask_job.png");
  MvJob job = mvMaskImageFileAsync(dev.handle, photo.c_str(), job_out.c_str(), &a);
  ASSERT_TRUE(job);
  EXPECT_EQ(mvWaitJob(job), MV_ERROR_NONE) << mvGetJobMessage(job);
  mvReleaseJob(job);
  EXPECT_EQ(file_bytes(job_out), file_bytes(out));
  const std::string raii_out = temp_path("capi_mask_raii.png");
  megavox::Device cpp("device=" + GetParam().selector());
  cpp.mask_async(photo, raii_out, a).finish();
  EXPECT_EQ(file_bytes(raii_out), file_bytes(out));
}

TEST_P(CApiFilesTest, MaskFailuresComeWithTheirCodes) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string photo = square_photo("capi_square_err.ppm"), out = temp_path("capi_mask_err.png");
  MvMaskArguments a;
  mvInitMaskArguments(&a);
  std::string m;
  EXPECT_EQ(mvMaskImageFile(dev.handle, photo.c_str(), out.c_str(), &a), MV_ERROR_INVALID_ARGUMENT);  // no start
  EXPECT_EQ(last_error(dev.handle, &m), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(m.find("no start"), std::string::npos) << m;
  a.hasRect = true;
  const uint32_t past[4] = {40, 20, 20, 20};
  std::memcpy(a.rect, past, sizeof past);
  EXPECT_EQ(mvMaskImageFile(dev.handle, photo.c_str(), out.c_str(), &a), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(last_error(dev.handle, &m), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(m.find("the box [40, 20, 20, 20] reaches past the 48 x 32 image"), std::string::npos) << m;
  const uint32_t inside[4] = {12, 4, 24, 24};
  std::memcpy(a.rect, inside, sizeof inside);
  EXPECT_EQ(mvMaskImageFile(dev.handle, "/no/such/photo.png", out.c_str(), &a), MV_ERROR_IO);
  const std::string text = temp_path("capi_not_an_image.png");
  std::ofstream(text) << "not an image";
  EXPECT_EQ(mvMaskImageFile(dev.handle, text.c_str(), out.c_str(), &a), MV_ERROR_INPUT);
  a.model = "/no/such/model.mvm";
  EXPECT_EQ(mvMaskImageFile(dev.handle, photo.c_str(), out.c_str(), &a), MV_ERROR_IO);
  EXPECT_FALSE(fs::exists(out));
}

TEST_P(CApiFilesTest, ViewCamerasAndPicturesWritten) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  MvBuildArguments b;
  mvInitBuildArguments(&b);
  b.resolution = 32;
  MvScene scene = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &b);
  ASSERT_TRUE(scene) << mvGetDeviceLastErrorMessage(dev.handle);
  MvCamera c;
  ASSERT_EQ(mvGetSceneViewCamera(scene, "front", 0, &c), MV_ERROR_NONE);
  Bounds bounds;
  for (int a = 0; a < 3; ++a) bounds.lo[a] = -1, bounds.hi[a] = 1;
  const Camera want = view_camera(bounds, "front", MV_DEFAULT_FOV);
  EXPECT_EQ(c.fov, MV_DEFAULT_FOV);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(c.eye[a], want.eye[a], 1e-6);
    EXPECT_NEAR(c.target[a], want.target[a], 1e-6);
  }
  EXPECT_EQ(mvGetSceneViewCamera(scene, "sideways", 0, &c), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_INVALID_ARGUMENT);

  MvRenderArguments r;
  mvInitRenderArguments(&r);
  r.width = 40;
  r.height = 30;
  std::vector<uint8_t> rgba(40 * 30 * 4);
  ASSERT_EQ(mvRenderScene(scene, nullptr, &r, rgba.data(), 0), MV_ERROR_NONE);
  mvReleaseScene(scene);
  for (const char* name : {"capi_picture.png", "capi_picture.jpg"}) {
    const std::string path = temp_path(name);
    ASSERT_EQ(mvWriteImage(path.c_str(), rgba.data(), 40, 30, 0), MV_ERROR_NONE) << mvGetDeviceLastErrorMessage(nullptr);
    const RasterImage back = io::read_image(path);
    EXPECT_EQ(back.width, 40u);
    EXPECT_EQ(back.height, 30u);
    EXPECT_EQ(back.channels, 3u);
    if (std::strstr(name, ".png")) {
      for (size_t i = 0; i < 40 * 30; ++i) {
        for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(back.samples[3 * i + ch], rgba[4 * i + ch]) << i;
      }
    }
  }
  EXPECT_EQ(mvWriteImage("/no/such/folder/x.png", rgba.data(), 40, 30, 0), MV_ERROR_IO);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_IO);
  EXPECT_EQ(mvWriteImage(temp_path("capi_x.png").c_str(), nullptr, 40, 30, 0), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvWriteImage(temp_path("capi_x.png").c_str(), rgba.data(), 40, 30, 8), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT);

  EXPECT_GT(mvGetHostMemoryBudget(nullptr), 0u);
  CDevice budgeted(GetParam(), "host_memory=3G");
  EXPECT_EQ(mvGetHostMemoryBudget(budgeted.handle), uint64_t{3} << 30);
}

MV_INSTANTIATE_ON_ALL_DEVICES(CApiFilesTest);

}  // namespace
}  // namespace mv::test::capi

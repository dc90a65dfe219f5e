// The C API on every device: builds (file and memory) against the C++ API, ray queries and pictures against
// mv::Tracer and mv::render, errors through codes, messages and the error function, cancels, jobs.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "scene_build.h"
#include "megavox/build.h"
#include "megavox/megavox.hpp"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "capi_fixture.h"
#include "test_support.h"
#include "option_words.h"

namespace mv::test::capi {
namespace {

class CApiTest : public ::testing::TestWithParam<DeviceInfo> {};

MvBuildArguments args_at(uint32_t resolution, const char* format, const std::string& output) {
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.resolution = resolution;
  a.format = format;
  a.output = output.empty() ? nullptr : output.c_str();
  return a;
}

bool same_file(const std::string& a, const std::string& b) {
  const auto x = file_bytes(a), y = file_bytes(b);
  return !x.empty() && x == y;
}

TEST_P(CApiTest, MemoryAndFileBuildsWriteTheBytesOfTheCppBuild) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  const std::string ply = temp_path("octa.ply"), from_mem = temp_path("mem.mvx"), from_file = temp_path("file.mvx"),
                    from_cpp = temp_path("cpp.mvx");
  write_ply(ply, m.positions, m.indices);
  for (const char* format : {"svdag", "ssvdag"}) {
    SCOPED_TRACE(format);
    MvBuildArguments a = args_at(32, format, from_mem);
    MvScene s1 = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a);
    ASSERT_TRUE(s1) << mvGetDeviceLastErrorMessage(dev.handle);
    a.output = from_file.c_str();
    MvScene s2 = mvBuildSceneFromFile(dev.handle, ply.c_str(), &a);
    ASSERT_TRUE(s2) << mvGetDeviceLastErrorMessage(dev.handle);
    BuildOptions o;
    o.input = ply;
    o.output = from_cpp;
    o.resolution = 32;
    o.encoding = parse_encoding(format);
    build_mvx(shared_device(GetParam()), o);
    EXPECT_TRUE(same_file(from_mem, from_cpp));
    EXPECT_TRUE(same_file(from_file, from_cpp));
    MvSceneInfo info;
    ASSERT_EQ(mvGetSceneInfo(s1, &info), MV_ERROR_NONE);
    const MvxFile f = read_mvx(from_cpp);
    EXPECT_STREQ(info.encoding, format);
    EXPECT_EQ(info.resolution, 32u);
    EXPECT_EQ(info.voxels, f.voxels);
    EXPECT_EQ(info.bytes, open_paged_mvx(from_cpp).words * 4);  // the paged node stream, as the file stores it
    EXPECT_EQ(info.voxelSize, f.grid.voxel_size);
    EXPECT_EQ(info.lower[1], -1.0);
    EXPECT_EQ(info.upper[2], 1.0);
    // a scene without an output file, then saved: the same bytes again
    MvBuildArguments none = args_at(32, format, "");
    MvScene s3 = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &none);
    ASSERT_TRUE(s3) << mvGetDeviceLastErrorMessage(dev.handle);
    const std::string saved = temp_path("saved.mvx");
    ASSERT_EQ(mvSaveScene(s3, saved.c_str()), MV_ERROR_NONE);
    EXPECT_TRUE(same_file(saved, from_cpp));
    mvReleaseScene(s1);
    mvReleaseScene(s2);
    mvReleaseScene(s3);
  }
}

TEST_P(CApiTest, RayQueriesAndPicturesEqualTheCppApi) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  const std::string path = temp_path("trace.mvx");
  for (const char* format : {"svo", "ussvdag", "ssvdag"}) {
    SCOPED_TRACE(format);
    MvBuildArguments a = args_at(64, format, path);
    MvScene built = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a);
    ASSERT_TRUE(built) << mvGetDeviceLastErrorMessage(dev.handle);
    mvReleaseScene(built);
    MvScene scene = mvOpenScene(dev.handle, path.c_str());
    ASSERT_TRUE(scene) << mvGetDeviceLastErrorMessage(dev.handle);
    MvSceneInfo info;
    ASSERT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);
    const std::vector<MvTraceRay> rays = random_rays(info, 3000, 7);
    std::vector<MvTraceHit> hits(rays.size());
    ASSERT_EQ(mvTraceRays(scene, rays.data(), hits.data(), rays.size(), nullptr), MV_ERROR_NONE)
        << mvGetDeviceLastErrorMessage(dev.handle);

    const MvxFile file = read_mvx(path);
    Tracer tracer(shared_device(GetParam()), file);
    std::vector<Ray> cpp(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      std::memcpy(cpp[i].origin, rays[i].org, 12);
      std::memcpy(cpp[i].direction, rays[i].dir, 12);
      cpp[i].tmax = rays[i].tmax;
    }
    const std::vector<RayHit> want = tracer.trace(cpp);
    size_t hit_count = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_FALSE(want[i].gave_up);
      if (!want[i].hit) {
        EXPECT_TRUE(std::isinf(hits[i].t)) << "ray " << i;
        continue;
      }
      ++hit_count;
      EXPECT_EQ(hits[i].t, want[i].t) << "ray " << i;
      EXPECT_EQ(hits[i].level, want[i].level);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(hits[i].cell[k], want[i].cell[k]) << "ray " << i;
        EXPECT_EQ(hits[i].normal[k], want[i].normal[k]) << "ray " << i;
      }
    }
    EXPECT_GT(hit_count, rays.size() / 4);
    EXPECT_LT(hit_count, rays.size());

    MvRenderArguments r;
    mvInitRenderArguments(&r);
    r.width = 48;
    r.height = 32;
    r.aoSamples = 2;
    const size_t stride = 48 * 4 + 16;  // rows padded: the padding stays as it was
    std::vector<uint8_t> rgba(stride * 32, 7);
    ASSERT_EQ(mvRenderScene(scene, nullptr, &r, rgba.data(), stride), MV_ERROR_NONE) << mvGetDeviceLastErrorMessage(dev.handle);
    RenderOptions o;
    o.width = 48;
    o.height = 32;
    o.ao_samples = 2;
    const RenderResult ref = render(tracer, view_camera(file.bounds, "iso"), o);
    for (uint32_t y = 0; y < 32; ++y)
      for (uint32_t x = 0; x < 48; ++x) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(rgba[y * stride + 4 * x + c], ref.image.rgb[(y * 48 + x) * 3 + c]);
        ASSERT_EQ(rgba[y * stride + 4 * x + 3], 255);
      }
    EXPECT_EQ(rgba[stride - 1], 7);
    mvReleaseScene(scene);
  }
}

struct Seen {
  int calls = 0;
  MvError code = MV_ERROR_NONE;
  std::string message;
};

void on_error(void* user, MvError code, const char* message) {
  auto* s = static_cast<Seen*>(user);
  ++s->calls;
  s->code = code;
  s->message = message;
}

TEST_P(CApiTest, ErrorsComeAsCodesMessagesAndCallbacks) {
  EXPECT_EQ(mvNewDevice("bogus=1"), nullptr);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mvGetDeviceLastErrorMessage(nullptr)).find("bogus"), std::string::npos);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_NONE);  // read once, then cleared
  EXPECT_EQ(mvNewDevice("memory=lots"), nullptr);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mvNewDevice("kernel_shape=wide"), nullptr);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mvGetDeviceLastErrorMessage(nullptr)).find("gpu"), std::string::npos);
  MvDevice shaped = mvNewDevice(("device=" + GetParam().selector() + ",memory=64M,kernel_shape=gpu").c_str());
  EXPECT_NE(shaped, nullptr);
  if (shaped) mvReleaseDevice(shaped);
  EXPECT_EQ(mvNewDevice("device=no-such-device-anywhere"), nullptr);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_UNSUPPORTED_DEVICE);
  EXPECT_STREQ(mvGetErrorString(MV_ERROR_CANCELLED), "MV_ERROR_CANCELLED");

  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  Seen seen;
  mvSetDeviceErrorFunction(dev.handle, on_error, &seen);
  EXPECT_EQ(mvOpenScene(dev.handle, "/no/such/file.mvx"), nullptr);
  EXPECT_EQ(seen.calls, 1);
  EXPECT_EQ(seen.code, MV_ERROR_IO);
  EXPECT_NE(seen.message.find("/no/such/file.mvx"), std::string::npos) << seen.message;
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_IO);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_NONE);

  const Mesh m = octahedron();
  std::vector<uint32_t> bad = m.indices;
  bad[5] = 6;
  const std::string out = temp_path("bad.mvx");
  MvBuildArguments a = args_at(16, "svdag", out);
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, bad.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_INPUT);
  EXPECT_NE(seen.message.find("names vertex 6"), std::string::npos) << seen.message;
  std::vector<float> nan_pos = m.positions;
  nan_pos[4] = NAN;
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, nan_pos.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_NE(seen.message.find("not finite"), std::string::npos) << seen.message;
  a.format = "octree";
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_INVALID_ARGUMENT);
  a = args_at(24, "svdag", out);
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_NE(seen.message.find("power of two"), std::string::npos) << seen.message;
  a = args_at(16, "svdag", out);
  a.byteSize = 8;
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_NE(seen.message.find("byteSize"), std::string::npos);
  // the library's advice in its own terms, not the CLI's flags
  a = args_at(1u << 21, "svdag", out);
  a.cube = 8;
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_OUT_OF_MEMORY);
  EXPECT_NE(seen.message.find("raise the cube size to"), std::string::npos) << seen.message;
  EXPECT_EQ(seen.message.find("--"), std::string::npos) << seen.message;
  EXPECT_FALSE(std::filesystem::exists(out));

  a = args_at(16, "svdag", "");
  MvScene scene = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a);
  ASSERT_TRUE(scene);
  const int before = seen.calls;
  MvTraceHit hit;
  EXPECT_EQ(mvTraceRays(scene, nullptr, &hit, 1, nullptr), MV_ERROR_INVALID_ARGUMENT);
  MvTraceRay inf_ray = {{INFINITY, 0, 0}, {1, 0, 0}, INFINITY};
  EXPECT_EQ(mvTraceRays(scene, &inf_ray, &hit, 1, nullptr), MV_ERROR_INPUT);
  EXPECT_NE(seen.message.find("non-finite"), std::string::npos) << seen.message;
  MvRenderArguments r;
  mvInitRenderArguments(&r);
  r.shading = "glossy";
  std::vector<uint8_t> px(size_t{r.width} * r.height * 4);
  EXPECT_EQ(mvRenderScene(scene, nullptr, &r, px.data(), 0), MV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(seen.message.find("glossy"), std::string::npos) << seen.message;
  EXPECT_EQ(seen.calls, before + 3);
  EXPECT_EQ(mvGetSceneInfo(scene, nullptr), MV_ERROR_INVALID_ARGUMENT);
  mvReleaseScene(scene);  // the device outlives it; a scene would also keep it alive

  // the RAII layer turns the same errors into megavox::Error
  megavox::Device cpp("device=" + GetParam().selector());
  try {
    cpp.open("/no/such/file.mvx");
    ADD_FAILURE() << "no exception";
  } catch (const megavox::Error& e) {
    EXPECT_EQ(e.code(), MV_ERROR_IO);
    EXPECT_NE(std::string(e.what()).find("/no/such/file.mvx"), std::string::npos);
  }
  EXPECT_THROW(megavox::Device("device=no-such-device-anywhere"), megavox::Error);
  megavox::Scene s = cpp.build(m.positions, m.indices, &a);
  megavox::Scene copy = s;  // retained
  s = megavox::Scene();
  EXPECT_EQ(copy.info().resolution, 16u);
}

bool stop_at_voxelize(void* user, const char* stage, double) {
  static_cast<std::vector<std::string>*>(user)->push_back(stage);
  return std::strcmp(stage, "voxelize") != 0;
}

TEST_P(CApiTest, AProgressFunctionCancelsAndNoFileIsLeft) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  const std::string out = temp_path("cancelled.mvx");
  std::vector<std::string> stages;
  MvBuildArguments a = args_at(64, "ssvdag", out);
  a.progress = stop_at_voxelize;
  a.progressUserPtr = &stages;
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_CANCELLED);
  EXPECT_NE(std::string(mvGetDeviceLastErrorMessage(dev.handle)).find("voxelize"), std::string::npos);
  ASSERT_FALSE(stages.empty());
  EXPECT_EQ(stages.front(), "read");
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
}

// Holds the job at its first progress point until the test lets it go.
struct Gate {
  std::atomic<bool> reached{false}, open{false};
};
bool wait_at_gate(void* user, const char*, double) {
  auto* g = static_cast<Gate*>(user);
  g->reached = true;
  while (!g->open) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return true;
}

TEST_P(CApiTest, JobsBuildReportProgressAndCancel) {
  CDevice dev(GetParam(), "memory=256M");
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  const std::string ply = temp_path("job.ply");
  write_ply(ply, m.positions, m.indices);
  // several jobs at once on one device: serialised by it, each done, the budget never passed
  std::vector<std::string> outs;
  std::vector<MvJob> jobs;
  for (int i = 0; i < 3; ++i) {
    outs.push_back(temp_path("job" + std::to_string(i) + ".mvx"));
    MvBuildArguments a = args_at(64, i % 2 ? "ssvdag" : "svdag", outs.back());
    jobs.push_back(i == 1 ? mvBuildSceneFromMemoryAsync(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a)
                          : mvBuildSceneFromFileAsync(dev.handle, ply.c_str(), &a));
    ASSERT_TRUE(jobs.back()) << mvGetDeviceLastErrorMessage(dev.handle);
  }
  for (MvJob j : jobs) {
    EXPECT_EQ(mvWaitJob(j), MV_ERROR_NONE) << mvGetJobMessage(j);
    double f = 0;
    EXPECT_EQ(mvGetJobStatus(j, &f), MV_JOB_DONE);
    EXPECT_EQ(f, 1.0);
    MvScene s = mvGetJobScene(j);
    ASSERT_TRUE(s);
    MvSceneInfo info;
    ASSERT_EQ(mvGetSceneInfo(s, &info), MV_ERROR_NONE);
    EXPECT_EQ(info.resolution, 64u);
    mvReleaseScene(s);
    mvReleaseJob(j);
  }
  for (const auto& o : outs) EXPECT_TRUE(std::filesystem::exists(o));
  MvDeviceInfo di;
  ASSERT_EQ(mvGetDeviceInfo(dev.handle, &di), MV_ERROR_NONE);
  EXPECT_EQ(di.memoryBudget, uint64_t{256} << 20);
  EXPECT_LE(di.memoryUsed, di.memoryBudget);

  // a job cancelled mid-build: cancelled, no scene, no file
  Gate gate;
  const std::string out = temp_path("job_cancelled.mvx");
  MvBuildArguments a = args_at(64, "svdag", out);
  a.progress = wait_at_gate;
  a.progressUserPtr = &gate;
  MvJob job = mvBuildSceneFromFileAsync(dev.handle, ply.c_str(), &a);
  ASSERT_TRUE(job);
  while (!gate.reached) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(mvGetJobStatus(job, nullptr), MV_JOB_RUNNING);
  mvCancelJob(job);
  gate.open = true;
  EXPECT_EQ(mvWaitJob(job), MV_ERROR_CANCELLED);
  EXPECT_EQ(mvGetJobStatus(job, nullptr), MV_JOB_CANCELLED);
  EXPECT_EQ(mvGetJobScene(job), nullptr);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_INVALID_OPERATION);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
  mvReleaseJob(job);

  // a failing job says why
  MvBuildArguments bad = args_at(64, "svdag", "");
  MvJob failed = mvBuildSceneFromFileAsync(dev.handle, "/no/such/mesh.ply", &bad);
  ASSERT_TRUE(failed);
  EXPECT_EQ(mvWaitJob(failed), MV_ERROR_IO);
  EXPECT_EQ(mvGetJobStatus(failed, nullptr), MV_JOB_FAILED);
  EXPECT_NE(std::string(mvGetJobMessage(failed)).find("/no/such/mesh.ply"), std::string::npos);
  mvReleaseJob(failed);
}

TEST(CApiVersion, MatchesTheHeader) {
  EXPECT_EQ(mvGetVersion(), uint32_t(MV_VERSION_MAJOR * 10000 + MV_VERSION_MINOR * 100 + MV_VERSION_PATCH));
  EXPECT_STREQ(mvGetVersionString(), MV_VERSION_STRING);
  static_assert(sizeof(MvTraceHit) == 32 && sizeof(MvTraceRay) == 28);
}

// No device needed: only the C arguments' translation into BuildOptions.
TEST(CApiBuildArguments, CubeZeroIsTheSharedDefaultAndInCoreIsAskedByName) {
  MvDeviceTy device;
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  EXPECT_EQ(a.cube, 0u);
  EXPECT_EQ(mv::capi::build_options(&device, &a).cube, kDefaultCube);
  EXPECT_EQ(mv::capi::build_options(&device, nullptr).cube, kDefaultCube);
  EXPECT_EQ(BuildOptions{}.cube, kDefaultCube);
  a.cube = MV_CUBE_IN_CORE;
  EXPECT_EQ(mv::capi::build_options(&device, &a).cube, 0u);
  for (uint32_t cube : {8u, 512u, 1024u, 4096u}) {
    a.cube = cube;
    EXPECT_EQ(mv::capi::build_options(&device, &a).cube, cube);
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(CApiTest);

}  // namespace
}  // namespace mv::test::capi

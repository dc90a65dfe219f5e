// Handle lifetimes in the C API: a job released from its own progress function or from another thread while it
// runs, a device released from inside a call or before its scenes, a built scene that reads its file only when
// used, and the "gave up" hit (NaN) of a ray out of steps. Run under ASan and TSan (scripts/test.sh --sanitize,
// --sanitize=thread), where a handle freed too early is a report.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <thread>

#include "megavox/megavox.h"
#include "megavox/trace.h"
#include "capi_fixture.h"
#include "test_support.h"

namespace mv::test::capi {
namespace {

class CApiLifetimeTest : public ::testing::TestWithParam<DeviceInfo> {};

MvBuildArguments lifetime_args(uint32_t resolution, const std::string& output) {
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.resolution = resolution;
  a.output = output.empty() ? nullptr : output.c_str();
  return a;
}

std::string octahedron_ply() {
  const Mesh m = octahedron();
  const std::string ply = temp_path("lifetime_octa.ply");
  write_ply(ply, m.positions, m.indices);
  return ply;
}

// Waits (up to a minute) until `done` holds.
template <class F>
bool lifetime_eventually(F&& done) {
  for (int i = 0; i < 60000 && !done(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return done();
}

// A job whose progress function drops the caller's only reference to it: the job is cancelled, its thread
// finishes alone, and nothing it reads afterwards has been freed.
struct SelfRelease {
  std::shared_future<MvJob> handle;
  std::atomic<int> calls{0};
  std::atomic<bool> released{false};
};
bool release_own_job(void* user, const char*, double) {
  auto* s = static_cast<SelfRelease*>(user);
  if (++s->calls == 1) {
    mvReleaseJob(s->handle.get());  // the last reference, on the job's own thread
    s->released = true;
  }
  return true;
}

struct LifetimeErrorSeen {
  std::atomic<int> code{-1};
};
void lifetime_note_error(void* user, MvError code, const char*) { static_cast<LifetimeErrorSeen*>(user)->code = code; }

TEST_P(CApiLifetimeTest, JobReleasedFromItsOwnProgressFunction) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  LifetimeErrorSeen seen;
  mvSetDeviceErrorFunction(dev.handle, lifetime_note_error, &seen);
  const std::string ply = octahedron_ply(), out = temp_path("self_release.mvx");
  std::promise<MvJob> published;
  SelfRelease s;
  s.handle = published.get_future().share();
  MvBuildArguments a = lifetime_args(64, out);
  a.progress = release_own_job;
  a.progressUserPtr = &s;
  MvJob job = mvBuildSceneFromFileAsync(dev.handle, ply.c_str(), &a);
  ASSERT_TRUE(job) << mvGetDeviceLastErrorMessage(dev.handle);
  published.set_value(job);
  // the job stops as a cancelled one (its error is recorded on the device from its thread) and leaves no file
  ASSERT_TRUE(lifetime_eventually([&] { return seen.code.load() == MV_ERROR_CANCELLED; }));
  EXPECT_TRUE(s.released);
  EXPECT_EQ(s.calls.load(), 1);
  ASSERT_TRUE(lifetime_eventually([&] { return !std::filesystem::exists(out + ".tmp"); }));
  EXPECT_FALSE(std::filesystem::exists(out));
  mvSetDeviceErrorFunction(dev.handle, nullptr, nullptr);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the thread's last steps, watched by ASan
}

// A job released by another thread while it runs: the release cancels it and returns once it stopped.
struct RunGate {
  std::atomic<bool> reached{false}, open{false};
};
bool lifetime_hold_at_gate(void* user, const char*, double) {
  auto* g = static_cast<RunGate*>(user);
  g->reached = true;
  while (!g->open) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return true;
}

TEST_P(CApiLifetimeTest, JobReleasedFromAnotherThreadWhileItRuns) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string ply = octahedron_ply(), out = temp_path("released_running.mvx");
  RunGate gate;
  MvBuildArguments a = lifetime_args(64, out);
  a.progress = lifetime_hold_at_gate;
  a.progressUserPtr = &gate;
  MvJob job = mvBuildSceneFromFileAsync(dev.handle, ply.c_str(), &a);
  ASSERT_TRUE(job);
  ASSERT_TRUE(lifetime_eventually([&] { return gate.reached.load(); }));
  std::thread opener([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    gate.open = true;
  });
  mvReleaseJob(job);  // waits for the job to stop: the gate opens, the job sees the cancel
  opener.join();
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
}

// A synchronous build whose progress function releases the caller's only reference to the device: the call
// keeps the device until it returns, and the scene keeps it after.
struct DropDevice {
  MvDevice device = nullptr;
  bool dropped = false;
};
bool drop_device(void* user, const char*, double) {
  auto* d = static_cast<DropDevice*>(user);
  if (!d->dropped) {
    d->dropped = true;
    mvReleaseDevice(d->device);
  }
  return true;
}

TEST_P(CApiLifetimeTest, DeviceReleasedDuringACallAndBeforeItsScenes) {
  const std::string config = "device=" + GetParam().selector();
  MvDevice device = mvNewDevice(config.c_str());
  ASSERT_TRUE(device) << mvGetDeviceLastErrorMessage(nullptr);
  const Mesh m = octahedron();
  DropDevice d{device};
  MvBuildArguments a = lifetime_args(32, "");
  a.progress = drop_device;
  a.progressUserPtr = &d;
  MvScene scene = mvBuildSceneFromMemory(device, m.positions.data(), 6, m.indices.data(), 8, &a);
  ASSERT_TRUE(d.dropped);
  ASSERT_TRUE(scene) << mvGetDeviceLastErrorMessage(nullptr);
  // the device lives on in the scene alone: a second scene of it, traced and drawn after the caller let go
  a.progress = nullptr;
  MvScene second = mvBuildSceneFromMemory(device, m.positions.data(), 6, m.indices.data(), 8, &a);
  ASSERT_TRUE(second);
  MvSceneInfo info;
  ASSERT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);
  const std::vector<MvTraceRay> rays = random_rays(info, 500, 3);
  std::vector<MvTraceHit> hits(rays.size()), again(rays.size());
  ASSERT_EQ(mvTraceRays(scene, rays.data(), hits.data(), rays.size(), nullptr), MV_ERROR_NONE);
  mvReleaseScene(scene);
  ASSERT_EQ(mvTraceRays(second, rays.data(), again.data(), rays.size(), nullptr), MV_ERROR_NONE);
  EXPECT_EQ(std::memcmp(hits.data(), again.data(), hits.size() * sizeof(MvTraceHit)), 0);
  std::vector<uint8_t> rgba(16 * 16 * 4);
  MvRenderArguments r;
  mvInitRenderArguments(&r);
  r.width = r.height = 16;
  EXPECT_EQ(mvRenderScene(second, nullptr, &r, rgba.data(), 0), MV_ERROR_NONE);
  mvReleaseScene(second);  // the device goes with it
}

// A built scene is the file its build wrote, read when first used: a caller that wants only the file (the
// service) never reads it back, and a scene without an output keeps a scratch file it removes when released.
TEST_P(CApiLifetimeTest, ABuiltSceneReadsItsFileOnFirstUse) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string ply = octahedron_ply(), out = temp_path("first_use.mvx");
  MvBuildArguments a = lifetime_args(32, out);
  MvScene scene = mvBuildSceneFromFile(dev.handle, ply.c_str(), &a);
  ASSERT_TRUE(scene) << mvGetDeviceLastErrorMessage(dev.handle);
  const std::string moved = out + ".moved";
  std::filesystem::rename(out, moved);
  MvSceneInfo info;
  EXPECT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_IO);  // not read yet, and its file is gone
  EXPECT_NE(std::string(mvGetDeviceLastErrorMessage(dev.handle)).find("first_use.mvx"), std::string::npos);
  std::filesystem::rename(moved, out);
  EXPECT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);  // a later use reads it
  EXPECT_EQ(info.resolution, 32u);
  std::filesystem::remove(out);
  EXPECT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);  // read once, kept
  mvReleaseScene(scene);

  const std::string scratch_dir = temp_path("lifetime_scratch");
  std::filesystem::create_directories(scratch_dir);
  const char* old = std::getenv("TMPDIR");
  const std::string saved = old ? old : "";
  setenv("TMPDIR", scratch_dir.c_str(), 1);
  MvScene own = mvBuildSceneFromFile(dev.handle, ply.c_str(), nullptr);
  if (old) setenv("TMPDIR", saved.c_str(), 1);
  else unsetenv("TMPDIR");
  ASSERT_TRUE(own) << mvGetDeviceLastErrorMessage(dev.handle);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(scratch_dir), {}), 1);
  EXPECT_EQ(mvGetSceneInfo(own, &info), MV_ERROR_NONE);
  mvReleaseScene(own);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(scratch_dir), {}), 0);
}

// A ray out of steps before it finds its voxel: t is NaN (neither a hit nor a miss), the rest zero.
TEST_P(CApiLifetimeTest, ARayOutOfStepsGivesUpWithNaN) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const Mesh m = octahedron();
  MvScene scene = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, nullptr);
  ASSERT_TRUE(scene) << mvGetDeviceLastErrorMessage(dev.handle);
  MvSceneInfo info;
  ASSERT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);
  const std::vector<MvTraceRay> rays = random_rays(info, 400, 11);
  MvTraceArguments t;
  mvInitTraceArguments(&t);
  std::vector<MvTraceHit> full(rays.size()), cut(rays.size());
  ASSERT_EQ(mvTraceRays(scene, rays.data(), full.data(), rays.size(), &t), MV_ERROR_NONE);
  t.maxSteps = 2;
  ASSERT_EQ(mvTraceRays(scene, rays.data(), cut.data(), rays.size(), &t), MV_ERROR_NONE);
  size_t gave_up = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!std::isnan(cut[i].t)) {  // found in two steps: the same answer as with room
      EXPECT_EQ(std::memcmp(&cut[i], &full[i], sizeof(MvTraceHit)), 0) << "ray " << i;
      continue;
    }
    ++gave_up;
    EXPECT_EQ(cut[i].level, 0u);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(cut[i].cell[k] | uint32_t(cut[i].normal[k]), 0u);
  }
  EXPECT_GT(gave_up, rays.size() / 4);
  for (const MvTraceHit& h : full) EXPECT_FALSE(std::isnan(h.t));
  mvReleaseScene(scene);
}

MV_INSTANTIATE_ON_ALL_DEVICES(CApiLifetimeTest);

}  // namespace
}  // namespace mv::test::capi

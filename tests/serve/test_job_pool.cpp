// The service's job pool on every device that opens (ocl:0, vk:0): a .mvx opened as a scene without a build,
// a queued render that keeps its scene's files while older jobs are dropped, cached scenes that make room for
// each other before a query is refused, and progress waits that wake on a change.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include "job_pool.h"
#include "megavox/megavox.h"
#include "megavox/mvx.h"

namespace fs = std::filesystem;
using mv::serve::HttpError;
using mv::serve::JobKind;
using mv::serve::JobPool;
using mv::serve::JobRequest;
using mv::serve::PoolOptions;

namespace {

// The selectors of this machine's devices that open (at least one).
std::vector<std::string> devices() {
  std::vector<std::string> out;
  for (const char* s : {"ocl:0", "vk:0"}) {
    const std::string config = std::string("device=") + s;
    if (MvDevice d = mvNewDevice(config.c_str())) {
      out.push_back(s);
      mvReleaseDevice(d);
    }
  }
  if (out.empty()) ADD_FAILURE() << "no device opens (ocl:0, vk:0)";
  return out;
}

// A fresh data folder for one test on one device.
std::string data_dir(const std::string& test, const std::string& device) {
  std::string name = test + "_" + device;
  for (char& c : name)
    if (c == ':') c = '_';
  const fs::path d = fs::temp_directory_path() / ("megavox_pool_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

const std::vector<float> kOctahedron = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
const std::vector<uint32_t> kFaces = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

// The octahedron built at `resolution` into `path` on `device` (encoding svo: the largest resident scene).
void build_mvx(const std::string& device, const std::string& path, uint32_t resolution) {
  const std::string config = "device=" + device;
  MvDevice d = mvNewDevice(config.c_str());
  ASSERT_TRUE(d);
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.resolution = resolution;
  a.format = "svo";
  a.output = path.c_str();
  MvScene s = mvBuildSceneFromMemory(d, kOctahedron.data(), 6, kFaces.data(), 8, &a);
  ASSERT_TRUE(s) << mvGetDeviceLastErrorMessage(d);
  mvReleaseScene(s);
  mvReleaseDevice(d);
}

void write_octahedron_ply(const std::string& path) {
  std::ofstream f(path);
  f << "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 8\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t i = 0; i < 6; ++i) f << kOctahedron[3 * i] << ' ' << kOctahedron[3 * i + 1] << ' ' << kOctahedron[3 * i + 2] << '\n';
  for (size_t i = 0; i < 8; ++i) f << "3 " << kFaces[3 * i] << ' ' << kFaces[3 * i + 1] << ' ' << kFaces[3 * i + 2] << '\n';
}

// Rays down the z axis through a grid of points over the model (hits and misses).
std::vector<MvTraceRay> down_rays(size_t side) {
  std::vector<MvTraceRay> rays;
  for (size_t i = 0; i < side; ++i)
    for (size_t j = 0; j < side; ++j) {
      MvTraceRay r{};
      r.org[0] = -1.2f + 2.4f * float(i) / float(side - 1);
      r.org[1] = -1.2f + 2.4f * float(j) / float(side - 1);
      r.org[2] = 3;
      r.dir[2] = -1;
      r.tmax = INFINITY;
      rays.push_back(r);
    }
  return rays;
}

// Waits for a job to end; returns its status.
std::string wait_end(JobPool& pool, const std::string& id) {
  for (int i = 0; i < 6000 && !pool.ended(id); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return pool.status(id).at("status");
}

std::string submit(JobPool& pool, JobRequest r) { return pool.submit(r, nullptr, "").at("id"); }

// A small picture of the scene of job `scene`.
JobRequest render_request(const std::string& scene) {
  JobRequest r;
  r.kind = JobKind::render;
  r.scene = scene;
  r.width = 32;
  r.height = 24;
  return r;
}

JobRequest open_request(const std::string& input) {
  JobRequest r;
  r.kind = JobKind::open;
  r.input = input;
  return r;
}

TEST(ServeJobPool, OpenJobAnswersRaysAsItsFileDoes) {
  for (const std::string& device : devices()) {
    SCOPED_TRACE(device);
    const std::string data = data_dir("open", device);
    build_mvx(device, data + "/octa.mvx", 64);
    { std::ofstream(data + "/broken.mvx") << "not a megavox file"; }
    PoolOptions o;
    o.device = device;
    o.workers = 1;
    o.data_dir = data;
    JobPool pool(o);
    const std::string id = submit(pool, open_request("octa.mvx"));
    ASSERT_EQ(wait_end(pool, id), "done") << pool.status(id).dump();
    EXPECT_FALSE(pool.status(id).contains("result"));
    EXPECT_EQ(pool.status(id).at("rays"), "/v1/jobs/" + id + "/rays");
    EXPECT_THROW(pool.result(id), HttpError);

    const std::vector<MvTraceRay> rays = down_rays(24);
    const std::vector<MvTraceHit> hits = pool.trace(id, rays.data(), rays.size());
    const std::string config = "device=" + device;
    MvDevice d = mvNewDevice(config.c_str());
    MvScene s = mvOpenScene(d, (data + "/octa.mvx").c_str());
    ASSERT_TRUE(s);
    std::vector<MvTraceHit> want(rays.size());
    ASSERT_EQ(mvTraceRays(s, rays.data(), want.data(), rays.size(), nullptr), MV_ERROR_NONE);
    EXPECT_EQ(std::memcmp(hits.data(), want.data(), hits.size() * sizeof(MvTraceHit)), 0);
    mvReleaseScene(s);
    mvReleaseDevice(d);

    // a render of the opened scene
    const std::string rid = submit(pool, render_request(id));
    EXPECT_EQ(wait_end(pool, rid), "done") << pool.status(rid).dump();

    // a file that is no .mvx fails, named; neither it nor the opened file is ever removed
    const std::string bad = submit(pool, open_request("broken.mvx"));
    EXPECT_EQ(wait_end(pool, bad), "failed");
    EXPECT_NE(pool.status(bad).at("message").get<std::string>().find("broken.mvx"), std::string::npos)
        << pool.status(bad).dump();
    pool.remove(id);
    pool.remove(bad);
    EXPECT_TRUE(fs::exists(data + "/octa.mvx"));
    EXPECT_TRUE(fs::exists(data + "/broken.mvx"));
  }
}

TEST(ServeJobPool, AQueuedRenderKeepsItsSceneWhenOldJobsAreDropped) {
  for (const std::string& device : devices()) {
    SCOPED_TRACE(device);
    const std::string data = data_dir("keep", device);
    write_octahedron_ply(data + "/octa.ply");
    PoolOptions o;
    o.device = device;
    o.workers = 1;          // jobs run in the order they came
    o.keep_finished = 1;    // each finished job drops the one before
    o.data_dir = data;
    JobPool pool(o);
    JobRequest build;
    build.kind = JobKind::build;
    build.input = "octa.ply";
    build.resolution = 32;
    const std::string a = submit(pool, build);
    ASSERT_EQ(wait_end(pool, a), "done");
    // b ends before the render starts and drops a from the pool: the render still reads a's file
    build.resolution = 16;
    const std::string b = submit(pool, build);
    const std::string r = submit(pool, render_request(a));
    ASSERT_EQ(wait_end(pool, r), "done") << pool.status(r).dump();
    EXPECT_THROW(pool.status(a), HttpError);  // dropped from the pool
    // with the render finished nothing holds a: its folder goes
    for (int i = 0; i < 500 && fs::exists(data + "/jobs/" + a); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_FALSE(fs::exists(data + "/jobs/" + a));
  }
}

TEST(ServeJobPool, CachedScenesMakeRoomBeforeAQueryIsRefused) {
  for (const std::string& device : devices()) {
    SCOPED_TRACE(device);
    const std::string data = data_dir("room", device);
    build_mvx(device, data + "/one.mvx", 512);
    fs::copy_file(data + "/one.mvx", data + "/two.mvx");
    build_mvx(device, data + "/big.mvx", 1024);
    mv::write_mvx(data + "/flat.mvx", mv::read_mvx(data + "/big.mvx"), mv::MvxPaging{0, mv::NodeOrder::level});
    // what one scene and a query hold on a device
    const std::vector<MvTraceRay> rays = down_rays(16);
    uint64_t used = 0;
    {
      const std::string config = "device=" + device;
      MvDevice d = mvNewDevice(config.c_str());
      MvScene s = mvOpenScene(d, (data + "/one.mvx").c_str());
      std::vector<MvTraceHit> hits(rays.size());
      ASSERT_EQ(mvTraceRays(s, rays.data(), hits.data(), rays.size(), nullptr), MV_ERROR_NONE);
      MvDeviceInfo info;
      mvGetDeviceInfo(d, &info);
      used = info.memoryUsed;
      mvReleaseScene(s);
      mvReleaseDevice(d);
    }
    ASSERT_GT(used, uint64_t{1} << 20);
    PoolOptions o;
    o.device = device;
    o.workers = 1;
    o.device_memory = 2 * (used + used / 2);  // two shares (the worker's, the queries'): room for one scene, not two
    o.data_dir = data;
    JobPool pool(o);
    const std::string one = submit(pool, open_request("one.mvx")), two = submit(pool, open_request("two.mvx"));
    ASSERT_EQ(wait_end(pool, one), "done");
    ASSERT_EQ(wait_end(pool, two), "done");
    const std::vector<MvTraceHit> first = pool.trace(one, rays.data(), rays.size());
    for (int round = 0; round < 2; ++round) {  // each query evicts the other scene
      std::vector<MvTraceHit> got;
      ASSERT_NO_THROW(got = pool.trace(two, rays.data(), rays.size()));
      EXPECT_EQ(std::memcmp(got.data(), first.data(), got.size() * sizeof(MvTraceHit)), 0);
      ASSERT_NO_THROW(got = pool.trace(one, rays.data(), rays.size()));
      EXPECT_EQ(std::memcmp(got.data(), first.data(), got.size() * sizeof(MvTraceHit)), 0);
    }
    // a query larger than the share is answered in batches that fit
    const std::vector<MvTraceRay> flood(o.device_memory / sizeof(MvTraceRay), rays[3]);
    const std::vector<MvTraceHit> many = pool.trace(one, flood.data(), flood.size());
    for (const MvTraceHit& h : many) ASSERT_EQ(std::memcmp(&h, &first[3], sizeof h), 0);
    // a scene that fits the share neither resident nor streamed (an unpaged file larger than it) is refused
    // with 503 once every other scene is evicted, and the next query that fits is answered
    const std::string flat = submit(pool, open_request("flat.mvx"));
    ASSERT_EQ(wait_end(pool, flat), "done");
    try {
      pool.trace(flat, rays.data(), rays.size());
      ADD_FAILURE() << "a scene past the device share was answered";
    } catch (const HttpError& e) {
      EXPECT_EQ(e.status, 503) << e.what();
    }
    std::vector<MvTraceHit> after;
    ASSERT_NO_THROW(after = pool.trace(two, rays.data(), rays.size()));
    EXPECT_EQ(std::memcmp(after.data(), first.data(), after.size() * sizeof(MvTraceHit)), 0);
  }
}

TEST(ServeJobPool, ProgressWaitsWakeOnAChange) {
  const std::string device = devices().at(0);
  const std::string data = data_dir("wake", device);
  build_mvx(device, data + "/octa.mvx", 16);
  PoolOptions o;
  o.device = device;
  o.workers = 1;
  o.data_dir = data;
  JobPool pool(o);
  const uint64_t seen = pool.wait_change(0, std::chrono::steady_clock::now());
  auto woke = std::async(std::launch::async, [&] {
    return pool.wait_change(seen, std::chrono::steady_clock::now() + std::chrono::seconds(60));
  });
  EXPECT_EQ(woke.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);  // nothing changed
  const auto start = std::chrono::steady_clock::now();
  const std::string id = submit(pool, open_request("octa.mvx"));
  EXPECT_GT(woke.get(), seen);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
  wait_end(pool, id);
}

}  // namespace

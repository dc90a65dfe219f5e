#include "job_pool.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>

#include "serve_error.h"
#include "data_path.h"
#include "job_run.h"
#include "job_words.h"

namespace mv::serve {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct JobPool::Job {
  std::string id;
  JobRequest request;
  std::string dir, input, result;  // the job's folder, the input file, the result file
  std::string seeds, model;        // a mask's seed map and model under --data-dir ("" when none)
  std::string status = "queued";   // queued, running, done, failed, cancelled
  double fraction = 0;
  std::string stage = "queued", message;  // stage: the running step; once the job ends, its status
  MvError code = MV_ERROR_NONE;          // a failed job's kind of failure
  std::atomic<bool> cancel{false};
  bool deleted = false;  // removed while running: its files go when it ends
  Clock::time_point created = Clock::now(), started{}, ended{};
  // A render's scene: the build or open job it draws, held (files included) until the render is gone, so that
  // dropping old finished jobs never takes a file a queued render still reads.
  std::shared_ptr<Job> scene_job;
  std::atomic<bool> discard{false};  // dropped from the pool: its folder goes with the last reference to it

  // The .mvx its scene is: a build's result, an open job's input (a file of the user's, never removed).
  const std::string& scene_file() const { return request.kind == JobKind::open ? input : result; }
  bool has_scene() const { return request.kind == JobKind::build || request.kind == JobKind::open; }
  ~Job() {
    std::error_code ec;
    if (discard) fs::remove_all(dir, ec);
  }
};

namespace {

constexpr size_t kScenesCached = 8;  // scenes kept uploaded on the query context

std::string new_id() {
  static std::mutex m;
  static std::mt19937_64 rng(std::random_device{}());
  std::lock_guard<std::mutex> g(m);
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(rng()));
  return text;
}

MvDevice open_context(const std::string& selector, uint64_t budget, uint64_t host) {
  std::string config = "memory=" + std::to_string(budget);
  if (!selector.empty()) config += ",device=" + selector;
  if (host) config += ",host_memory=" + std::to_string(host);
  MvDevice d = mvNewDevice(config.c_str());
  if (!d) {
    const std::string message = mvGetDeviceLastErrorMessage(nullptr);
    throw ServeError("serve: cannot open the device: " + message, mvGetDeviceError(nullptr));
  }
  return d;
}

// An upload's file name keeps only its extension (assimp picks the reader by it; point clouds and images are
// told by their first bytes).
std::string input_name(const std::string& upload_name, JobKind kind) {
  static const std::regex ext("\\.[A-Za-z0-9]{1,8}");
  const std::string e = fs::path(upload_name).extension().string();
  if (std::regex_match(e, ext)) return "input" + e;
  return kind == JobKind::render ? "input.mvx" : kind == JobKind::mask ? "input.png" : "input.ply";
}

std::string result_name(const JobRequest& r) {
  switch (r.kind) {
    case JobKind::build: return "result.mvx";
    case JobKind::open: return "";  // its scene is the input
    case JobKind::points: return r.format == "3dtiles" ? "result.3tz" : "result.mvx";
    default: return "result.png";
  }
}

std::string content_type(const JobRequest& r) {
  if (r.kind == JobKind::render || r.kind == JobKind::mask) return "image/png";
  if (r.kind == JobKind::points && r.format == "3dtiles") return "application/vnd.maxar.archive.3tz+zip";
  return "application/octet-stream";
}

}  // namespace

JobPool::JobPool(const PoolOptions& o) : options_(o) {
  if (o.workers < 1 || o.workers > 64) throw ServeError("serve: --max-jobs must be from 1 to 64");
  max_queue_ = o.max_queue ? o.max_queue : 4 * o.workers;
  uint64_t total = o.device_memory;
  if (!total) {
    MvDevice probe = open_context(o.device, 0, 0);
    MvDeviceInfo info;
    mvGetDeviceInfo(probe, &info);
    total = info.memoryBudget;
    mvReleaseDevice(probe);
  }
  // every worker and the ray-query context get an equal share, so together they never pass the budget
  budget_ = total / (o.workers + 1);
  const uint64_t host = (o.host_memory ? o.host_memory : mvGetHostMemoryBudget(nullptr)) / o.workers;
  try {
    for (uint32_t i = 0; i < o.workers; ++i) devices_.push_back(open_context(o.device, budget_, host));
    query_device_ = open_context(o.device, budget_, 0);
  } catch (...) {
    for (MvDevice d : devices_) mvReleaseDevice(d);
    throw;
  }
  fs::create_directories(fs::path(o.data_dir) / "jobs");
  for (size_t i = 0; i < devices_.size(); ++i) threads_.emplace_back([this, i] { work(i); });
}

JobPool::~JobPool() {
  shutdown();
  for (auto& [id, s] : scenes_) mvReleaseScene(s);
  for (MvDevice d : devices_) mvReleaseDevice(d);
  mvReleaseDevice(query_device_);
}

json JobPool::submit(const JobRequest& r, const std::string* upload, const std::string& upload_name) {
  auto job = std::make_shared<Job>();
  job->request = r;
  {
    std::lock_guard<std::mutex> g(lock_);
    if (stopping_) throw HttpError(503, "the server is shutting down", 5);
    if (queue_.size() >= max_queue_)
      throw HttpError(503, "the job queue is full (" + std::to_string(max_queue_) + " waiting); try again shortly", 1);
    if (!upload && r.input.empty() && r.scene.empty()) throw HttpError(400, "job: \"input\" is missing (a file under the data folder)");
    if (!r.scene.empty()) {
      auto it = jobs_.find(r.scene);
      if (it == jobs_.end() || it->second->deleted) throw HttpError(404, "job: scene '" + r.scene.substr(0, 64) + "' is no job");
      if (!it->second->has_scene() || it->second->status != "done")
        throw HttpError(409, "job: scene '" + r.scene + "' is not a finished build or open job");
      job->scene_job = it->second;
      job->input = it->second->scene_file();
    }
  }
  try {
    if (!r.input.empty()) job->input = resolve_data_path(options_.data_dir, r.input);
    if (!r.seeds.empty()) job->seeds = resolve_data_path(options_.data_dir, r.seeds, "seeds");
    if (!r.model.empty()) job->model = resolve_data_path(options_.data_dir, r.model, "model");
  } catch (const ServeError& e) {
    throw HttpError(400, e.what());
  }
  do job->id = new_id();
  while (fs::exists(fs::path(options_.data_dir) / "jobs" / job->id));
  job->dir = (fs::path(options_.data_dir) / "jobs" / job->id).string();
  fs::create_directories(job->dir);
  if (!result_name(r).empty()) job->result = (fs::path(job->dir) / result_name(r)).string();
  if (upload) {
    job->input = (fs::path(job->dir) / input_name(upload_name, r.kind)).string();
    std::ofstream out(job->input, std::ios::binary);
    out.write(upload->data(), static_cast<std::streamsize>(upload->size()));
    out.close();
    if (!out) {
      fs::remove_all(job->dir);
      throw HttpError(507, "cannot store the upload in the data folder");
    }
  }
  std::lock_guard<std::mutex> g(lock_);
  if (stopping_ || queue_.size() >= max_queue_) {  // checked again: the upload took time
    fs::remove_all(job->dir);
    throw HttpError(503, stopping_ ? "the server is shutting down" : "the job queue is full; try again shortly", 1);
  }
  jobs_[job->id] = job;
  queue_.push_back(job);
  wake_.notify_one();
  changed_locked();
  return describe(*job);
}

std::shared_ptr<JobPool::Job> JobPool::find(const std::string& id) const {
  auto it = jobs_.find(id);
  if (it == jobs_.end() || it->second->deleted) throw HttpError(404, "no job '" + id.substr(0, 64) + "'");
  return it->second;
}

json JobPool::describe(const Job& j) const {
  const auto now = Clock::now();
  const auto since = [&](Clock::time_point t) { return std::chrono::duration<double>(now - t).count(); };
  json d = {{"id", j.id},
            {"kind", kind_name(j.request.kind)},
            {"status", j.status},
            {"percentComplete", std::round(j.fraction * 1000) / 10},
            {"stage", j.stage},
            {"message", j.message},
            {"secondsQueued", j.status == "queued" ? since(j.created)
                                                   : std::chrono::duration<double>(j.started - j.created).count()}};
  if (j.status == "running") d["secondsRunning"] = since(j.started);
  if (j.status == "done" && !j.result.empty()) d["result"] = "/v1/jobs/" + j.id + "/result";
  if (j.status == "done" && j.has_scene()) d["rays"] = "/v1/jobs/" + j.id + "/rays";
  if (j.status == "failed") d["code"] = mvGetErrorString(j.code);
  return d;
}

json JobPool::status(const std::string& id) const {
  std::lock_guard<std::mutex> g(lock_);
  return describe(*find(id));
}

json JobPool::list() const {
  std::lock_guard<std::mutex> g(lock_);
  json all = json::array();
  for (const auto& [id, j] : jobs_)
    if (!j->deleted) all.push_back(describe(*j));
  return {{"jobs", all}};
}

json JobPool::cancel(const std::string& id) {
  std::lock_guard<std::mutex> g(lock_);
  auto j = find(id);
  j->cancel = true;
  changed_locked();
  return describe(*j);
}

bool JobPool::ended(const std::string& id) const {
  std::lock_guard<std::mutex> g(lock_);
  const std::string s = find(id)->status;
  return s != "queued" && s != "running";
}

void JobPool::remove(const std::string& id) {
  std::shared_ptr<Job> j;
  {
    std::lock_guard<std::mutex> g(lock_);
    j = find(id);
    j->cancel = true;
    j->deleted = true;
    changed_locked();
    if (j->status == "running") return;  // the worker deletes it when it stops
    j->discard = true;  // its folder goes with the last reference (a queued render may hold it)
    jobs_.erase(id);
    queue_.erase(std::remove(queue_.begin(), queue_.end(), j), queue_.end());
    finished_.erase(std::remove(finished_.begin(), finished_.end(), id), finished_.end());
  }
  forget_scene(id);
}

void JobPool::forget_scene(const std::string& id) {
  std::lock_guard<std::mutex> g(query_lock_);
  for (auto it = scenes_.begin(); it != scenes_.end(); ++it)
    if (it->first == id) {
      mvReleaseScene(it->second);
      scenes_.erase(it);
      return;
    }
}

void JobPool::changed_locked() {
  ++changes_;
  changed_.notify_all();
}

uint64_t JobPool::wait_change(uint64_t seen, Clock::time_point deadline) {
  std::unique_lock<std::mutex> g(lock_);
  changed_.wait_until(g, deadline, [&] { return changes_ != seen || stopping_; });
  return changes_;
}

JobPool::Result JobPool::result(const std::string& id) const {
  std::lock_guard<std::mutex> g(lock_);
  auto j = find(id);
  if (j->status != "done") throw HttpError(409, "job " + id + " is " + j->status + (j->message.empty() ? "" : ": " + j->message));
  if (j->result.empty()) throw HttpError(409, "job " + id + " is an open job: its scene answers rays and renders, it has no result file");
  return {j->result, content_type(j->request)};
}

MvScene JobPool::query_scene(const std::string& id, const std::string& path) {
  for (auto it = scenes_.begin(); it != scenes_.end(); ++it)
    if (it->first == id) {
      scenes_.splice(scenes_.begin(), scenes_, it);
      return it->second;
    }
  MvScene s = mvOpenScene(query_device_, path.c_str());
  if (!s) throw HttpError(500, std::string("cannot open the scene: ") + mvGetDeviceLastErrorMessage(query_device_));
  scenes_.emplace_front(id, s);
  if (scenes_.size() > kScenesCached) {
    mvReleaseScene(scenes_.back().second);
    scenes_.pop_back();
  }
  return s;
}

bool JobPool::evict_scene_besides(const std::string& id) {
  for (auto it = scenes_.rbegin(); it != scenes_.rend(); ++it)
    if (it->first != id) {
      mvReleaseScene(it->second);
      scenes_.erase(std::next(it).base());
      return true;
    }
  return false;
}

std::vector<MvTraceHit> JobPool::trace(const std::string& id, const MvTraceRay* rays, size_t count,
                                       std::vector<uint8_t>* rgba) {
  std::string path;
  {
    std::lock_guard<std::mutex> g(lock_);
    auto j = find(id);
    if (!j->has_scene())
      throw HttpError(409, "job " + id + " is a " + kind_name(j->request.kind) + " job; rays go to a build or an open job");
    if (j->status != "done") throw HttpError(409, "job " + id + " is " + j->status + ", not done");
    path = j->scene_file();
  }
  std::vector<MvTraceHit> hits(count);
  std::lock_guard<std::mutex> g(query_lock_);
  for (;;) {
    MvScene s = query_scene(id, path);
    if (rgba) rgba->assign(4 * count, 0);
    if (mvTraceRaysRgba(s, rays, hits.data(), rgba ? rgba->data() : nullptr, count, nullptr) == MV_ERROR_NONE)
      return hits;
    const MvError e = mvGetDeviceError(query_device_);
    const std::string m = mvGetDeviceLastErrorMessage(query_device_);
    // Out of device memory: the scenes used least recently make room, one by one, before the query is refused.
    if (e == MV_ERROR_OUT_OF_MEMORY && evict_scene_besides(id)) continue;
    throw HttpError(e == MV_ERROR_OUT_OF_MEMORY ? 503 : e == MV_ERROR_INPUT ? 400 : 500, m, 1);
  }
}

void JobPool::work(size_t worker) {
  MvDevice dev = devices_[worker];
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock<std::mutex> g(lock_);
      wake_.wait(g, [this] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      job = queue_.front();
      queue_.pop_front();
      job->status = "running";
      job->started = Clock::now();
      changed_locked();
    }
    if (job->cancel) {
      std::lock_guard<std::mutex> g(lock_);
      job->status = job->stage = "cancelled";
    } else {
      run(dev, *job);
    }
    finish(job);
  }
}

// Runs a job's runner (job_run.h), feeding its progress to the job's record and stopping it on a cancel or
// past the timeout. A job stopped either way is told by those flags: whatever the runner throws on its way
// out (the library may wrap the stop in its own error) is then no failure of the job's.
void JobPool::run(MvDevice dev, Job& job) {
  std::atomic<bool> timed_out{false};
  const auto report = [&](const std::string& stage, double fraction) {
    {
      std::lock_guard<std::mutex> g(lock_);
      job.stage = stage;
      job.fraction = std::max(job.fraction, std::min(fraction, 1.0));
      changed_locked();
    }
    if (std::chrono::duration<double>(Clock::now() - job.started).count() > options_.job_timeout) timed_out = true;
    return !job.cancel && !timed_out;
  };
  JobRun r{job.request, job.input, job.seeds, job.model, job.dir, job.result, report};
  std::string failure;
  MvError code = MV_ERROR_NONE;
  bool ok = false;
  try {
    switch (job.request.kind) {
      case JobKind::build: run_build(dev, r); break;
      case JobKind::render: run_render(dev, r); break;
      case JobKind::points: run_points(dev, r); break;
      case JobKind::mask: run_mask(dev, r); break;
      case JobKind::open: run_open(dev, r); break;
    }
    ok = true;
  } catch (const std::exception& e) {
    failure = message_of(e);
    code = code_of(e);
  }
  std::lock_guard<std::mutex> g(lock_);
  if (job.cancel) {
    job.status = "cancelled";
  } else if (!ok && timed_out) {
    job.status = "failed";
    job.message = "the job ran past the server's job timeout (" + std::to_string(int(options_.job_timeout)) + " s)";
    job.code = MV_ERROR_CANCELLED;
  } else if (!ok) {
    job.status = "failed";
    job.message = in_job_terms(failure);
    job.code = code;
  } else {
    job.status = "done";
    job.fraction = 1;
  }
  job.stage = job.status;
  changed_locked();
}

// Ends a job: a deleted one goes with its files, the oldest finished ones past --keep too (each folder with the
// last reference to its job: a queued render keeps its scene's).
void JobPool::finish(const std::shared_ptr<Job>& job) {
  std::vector<std::shared_ptr<Job>> gone;  // released here, outside the lock: their folders go then
  {
    std::lock_guard<std::mutex> g(lock_);
    job->ended = Clock::now();
    job->scene_job.reset();
    if (job->deleted) {
      jobs_.erase(job->id);
      gone.push_back(job);
    } else {
      if (job->status != "done" && !job->result.empty()) {  // nothing of a failed or cancelled job stays but its record
        std::error_code ec;
        fs::remove(job->result, ec);
      }
      finished_.push_back(job->id);
      while (finished_.size() > options_.keep_finished) {
        auto it = jobs_.find(finished_.front());
        if (it != jobs_.end()) {
          gone.push_back(it->second);
          jobs_.erase(it);
        }
        finished_.pop_front();
      }
    }
    for (auto& j : gone) j->discard = true;
    changed_locked();
  }
  for (auto& j : gone) forget_scene(j->id);
}

void JobPool::shutdown() {
  std::vector<std::shared_ptr<Job>> unfinished;
  {
    std::lock_guard<std::mutex> g(lock_);
    if (stopping_ && threads_.empty()) return;
    stopping_ = true;
    for (auto& [id, j] : jobs_) j->cancel = true;
    for (auto& j : queue_) j->status = j->stage = "cancelled";
    queue_.clear();
    wake_.notify_all();
    changed_locked();
  }
  for (auto& t : threads_) t.join();
  threads_.clear();
  std::lock_guard<std::mutex> g(lock_);
  std::error_code ec;
  for (auto& [id, j] : jobs_)
    if (j->status != "done") fs::remove_all(j->dir, ec);
}

}  // namespace mv::serve

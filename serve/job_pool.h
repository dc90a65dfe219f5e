// The jobs of `megavox serve`: a bounded queue, a pool of workers each running one job at a time on its own
// device context (the budget split evenly), per-job timeouts and cancels, results as files under
// DATA/jobs/ID/, and ray queries against finished builds (or .mvx files opened as scenes) on one more device
// context of their own, whose cached scenes make room for each other under memory pressure.
#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "megavox/megavox.h"
#include "job_request.h"

namespace mv::serve {

// A refusal with its HTTP status (and Retry-After seconds for 503).
struct HttpError : std::runtime_error {
  HttpError(int s, const std::string& m, int retry = 0) : std::runtime_error(m), status(s), retry_after(retry) {}
  int status;
  int retry_after;
};

struct PoolOptions {
  std::string device;          // selector (empty: the default device)
  uint64_t device_memory = 0;  // the whole device budget, split over the contexts (0: the device's default)
  uint64_t host_memory = 0;    // builds' host RAM, split over the workers (0: half the RAM)
  uint32_t workers = 2;        // --max-jobs: jobs running at once
  uint32_t max_queue = 0;      // jobs waiting at most (0: 4 per worker); past it 503 + Retry-After
  double job_timeout = 600;    // seconds a job may run
  uint32_t keep_finished = 256;  // finished jobs kept (the oldest are deleted with their files past it)
  std::string data_dir;
};

class JobPool {
 public:
  explicit JobPool(const PoolOptions& options);  // opens the device contexts; throws ServeError
  ~JobPool();
  JobPool(const JobPool&) = delete;
  JobPool& operator=(const JobPool&) = delete;

  // Queues a job: `upload` (may be null) holds the input's bytes, `upload_name` its file name (for the
  // extension). Returns its status. HttpError: 400 bad request (or files it names that are not under
  // --data-dir), 404/409 a render's scene, 503 queue full.
  nlohmann::json submit(const JobRequest& request, const std::string* upload, const std::string& upload_name);
  nlohmann::json status(const std::string& id) const;  // HttpError 404
  nlohmann::json list() const;
  nlohmann::json cancel(const std::string& id);  // 404
  void remove(const std::string& id);             // 404; cancels a running job, deletes its files
  bool ended(const std::string& id) const;        // 404

  struct Result {
    std::string path, content_type;
  };
  Result result(const std::string& id) const;  // 404, 409 (not done)

  // Ray queries against a finished build or open job (HttpError 404, 409; 400 for bad rays; 503 when the
  // query does not fit the device even with every other cached scene evicted).
  // rgba, when given, receives 4 bytes per ray: the hit's colour (mvTraceRaysRgba).
  std::vector<MvTraceHit> trace(const std::string& id, const MvTraceRay* rays, size_t count,
                                std::vector<uint8_t>* rgba = nullptr);

  // Waits until any job's record changes after `seen` (a count from an earlier call; 0 at first), the deadline
  // passes or the pool stops; returns the count now. For progress streams: they wake on a change, never poll.
  uint64_t wait_change(uint64_t seen, std::chrono::steady_clock::time_point deadline);

  // Stops taking jobs, cancels the queued and running ones, waits for the workers and deletes the files of
  // every job that did not finish. Idempotent.
  void shutdown();

  uint32_t workers() const { return static_cast<uint32_t>(devices_.size()); }
  uint64_t budget_per_context() const { return budget_; }
  uint32_t max_queue() const { return max_queue_; }

 private:
  struct Job;
  void work(size_t worker);
  void run(MvDevice dev, Job& job);
  void finish(const std::shared_ptr<Job>& job);
  std::shared_ptr<Job> find(const std::string& id) const;  // under lock_; 404
  nlohmann::json describe(const Job& job) const;            // under lock_
  MvScene query_scene(const std::string& id, const std::string& path);  // under query_lock_
  bool evict_scene_besides(const std::string& id);  // under query_lock_: the least recently used other scene
  void forget_scene(const std::string& id);          // takes query_lock_
  void changed_locked();                              // under lock_: a job's record changed

  PoolOptions options_;
  uint64_t budget_ = 0;
  uint32_t max_queue_ = 0;
  std::vector<MvDevice> devices_;  // one per worker
  MvDevice query_device_ = nullptr;

  mutable std::mutex lock_;
  std::condition_variable wake_;
  std::condition_variable changed_;  // changes_ moved
  uint64_t changes_ = 0;
  bool stopping_ = false;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::deque<std::string> finished_;  // ids, oldest first
  std::vector<std::thread> threads_;

  std::mutex query_lock_;
  std::list<std::pair<std::string, MvScene>> scenes_;  // most recently used first
};

}  // namespace mv::serve

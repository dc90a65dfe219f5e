// The C API: jobs, each on its own thread, with status, fraction done and cancel; the scene builds' jobs.
#include "job.h"

#include <algorithm>
#include <condition_variable>
#include <memory>
#include <thread>

#include "scene_build.h"

namespace mv::capi {

// What a job's thread and its handle share: the thread holds it to its end, so releasing the handle (even from
// the job's own progress function, on that thread) never frees what the running work reads.
struct JobState {
  MvDevice device = nullptr;  // retained
  JobWork work;
  std::atomic<bool> cancel{false};
  std::mutex lock;  // everything below
  std::condition_variable ended;
  MvJobStatus status = MV_JOB_QUEUED;
  double fraction = 0;
  std::string message;   // the stage, or the failure
  std::string returned;  // what mvGetJobMessage handed out last
  MvError error = MV_ERROR_NONE;
  MvScene scene = nullptr;

  ~JobState() {
    mvReleaseScene(scene);
    mvReleaseDevice(device);
  }
};

}  // namespace mv::capi

struct MvJobTy : mv::capi::RefCounted {
  std::shared_ptr<mv::capi::JobState> state;
  std::thread thread;

  // The last release cancels the work and waits for it to stop; from the job's own thread (its progress
  // function) it cannot wait, so the thread goes on alone, holding the state, and stops at once.
  ~MvJobTy() {
    state->cancel = true;
    if (thread.joinable()) {
      if (thread.get_id() == std::this_thread::get_id()) thread.detach();
      else thread.join();
    }
  }
};

namespace mv::capi {

namespace {

// A scene build's fraction from its stage's: voxelizing is most of an in-core build, the cubes most of an
// out-of-core one; the octree, reduction and encoding follow the last of those reports, then the file is written.
double scene_overall(const std::string& stage, double f) {
  f = std::clamp(f, 0.0, 1.0);
  if (stage == "read") return 0.2 * f;  // only out of core reports more than 0 here
  if (stage == "voxelize") return 0.2 + 0.5 * f;
  if (stage == "cubes") return 0.2 + 0.7 * f;
  if (stage == "write") return 0.95 + 0.05 * f;
  return 0;
}

void run(const std::shared_ptr<JobState>& job) {
  Progress progress = [job](const std::string& stage, double f) {
    if (job->cancel) throw ApiError(MV_ERROR_CANCELLED, "the job was cancelled during '" + stage + "'");
    {
      std::lock_guard<std::mutex> g(job->lock);
      job->status = MV_JOB_RUNNING;
      job->message = stage;
      job->fraction = std::max(job->fraction, std::clamp(job->work.overall(stage, f), 0.0, 1.0));
    }
    if (job->work.user) job->work.user(stage, f);
    if (job->cancel) throw ApiError(MV_ERROR_CANCELLED, "the job was cancelled during '" + stage + "'");
  };
  MvScene scene = nullptr;
  std::string failure;
  const MvError code = guard(job->device, [&] { scene = job->work.run(progress); }, &failure);
  std::lock_guard<std::mutex> g(job->lock);
  job->error = code;
  job->scene = scene;
  job->status = code == MV_ERROR_NONE ? MV_JOB_DONE : code == MV_ERROR_CANCELLED ? MV_JOB_CANCELLED : MV_JOB_FAILED;
  if (code == MV_ERROR_NONE) job->fraction = 1;
  job->message = failure;
  job->ended.notify_all();
}

// A scene build as a job: the input (arrays copied) and the options owned by the work.
MvJob start_scene_build(MvDevice device, BuildInput input, const MvBuildArguments* args) {
  auto in = std::make_shared<BuildInput>(std::move(input));
  if (in->path.empty()) in->mesh = {in->positions, in->indices};
  JobWork work;
  work.run = [device, in, options = build_options(device, args)](const Progress& progress) {
    return build_scene(device, *in, options, progress);
  };
  work.overall = scene_overall;
  work.user = user_progress(args);
  return start_job(device, std::move(work));
}

}  // namespace

MvJob start_job(MvDevice device, JobWork work) {
  auto job = std::make_unique<MvJobTy>();
  job->state = std::make_shared<JobState>();
  job->state->work = std::move(work);
  mvRetainDevice(device);
  job->state->device = device;
  job->thread = std::thread([state = job->state] { run(state); });
  return job.release();
}

Progress user_progress(MvProgressMonitorFunction f, void* user, const char* what) {
  if (!f) return {};
  const std::string name = what;
  return [f, user, name](const std::string& stage, double fraction) {
    if (!f(user, stage.c_str(), fraction))
      throw ApiError(MV_ERROR_CANCELLED, name + " cancelled by its progress function during '" + stage + "'");
  };
}

}  // namespace mv::capi

using namespace mv::capi;

extern "C" {

MvJob mvBuildSceneFromFileAsync(MvDevice device, const char* path, const MvBuildArguments* args) {
  MvJob job = nullptr;
  guard(device, [&] {
    require(device, "mvBuildSceneFromFileAsync: no device");
    job = start_scene_build(device, file_input(path), args);
  });
  return job;
}

MvJob mvBuildSceneFromMemoryAsync(MvDevice device, const float* vertices, size_t vertexCount, const uint32_t* indices,
                                  size_t triangleCount, const MvBuildArguments* args) {
  MvJob job = nullptr;
  guard(device, [&] {
    require(device, "mvBuildSceneFromMemoryAsync: no device");
    job = start_scene_build(device, memory_input(vertices, vertexCount, indices, triangleCount, true), args);
  });
  return job;
}

void mvRetainJob(MvJob job) { retain(job); }

void mvReleaseJob(MvJob job) { release(job); }

MvJobStatus mvGetJobStatus(MvJob job, double* fraction) {
  if (!job) {
    record_error(nullptr, MV_ERROR_INVALID_ARGUMENT, "mvGetJobStatus: no job");
    return MV_JOB_FAILED;
  }
  JobState& s = *job->state;
  std::lock_guard<std::mutex> g(s.lock);
  if (fraction) *fraction = s.fraction;
  return s.status;
}

const char* mvGetJobMessage(MvJob job) {
  if (!job) return "";
  JobState& s = *job->state;
  std::lock_guard<std::mutex> g(s.lock);
  s.returned = s.message;
  return s.returned.c_str();
}

void mvCancelJob(MvJob job) {
  if (job) job->state->cancel = true;
}

MvError mvWaitJob(MvJob job) {
  if (!job) {
    record_error(nullptr, MV_ERROR_INVALID_ARGUMENT, "mvWaitJob: no job");
    return MV_ERROR_INVALID_ARGUMENT;
  }
  JobState& s = *job->state;
  if (job->thread.get_id() == std::this_thread::get_id()) {  // its own progress function: it would never end
    record_error(s.device, MV_ERROR_INVALID_OPERATION, "mvWaitJob: called from the job's own progress function");
    return MV_ERROR_INVALID_OPERATION;
  }
  std::unique_lock<std::mutex> g(s.lock);
  s.ended.wait(g, [&s] { return s.status >= MV_JOB_DONE; });
  return s.error;
}

MvScene mvGetJobScene(MvJob job) {
  if (!job) {
    record_error(nullptr, MV_ERROR_INVALID_ARGUMENT, "mvGetJobScene: no job");
    return nullptr;
  }
  JobState& s = *job->state;
  const char* refusal = nullptr;
  {
    std::lock_guard<std::mutex> g(s.lock);
    if (s.status == MV_JOB_DONE && s.scene) {
      mvRetainScene(s.scene);
      return s.scene;
    }
    refusal = s.status != MV_JOB_DONE ? "mvGetJobScene: the job has not built its scene"
                                      : "mvGetJobScene: the job writes a file, not a scene";
  }
  record_error(s.device, MV_ERROR_INVALID_OPERATION, refusal);  // outside the lock: the error function may call in
  return nullptr;
}

}  // extern "C"

// The C API's jobs: any of its long calls (a scene build, a point-cloud build, a mask) run on a thread of their
// own, with status, fraction done, cancel and the failure's code and message.
#pragma once
#include <functional>
#include <string>

#include "handles.h"
#include "megavox/build.h"

namespace mv::capi {

struct JobWork {
  // The work, on the job's thread; `progress` throws ApiError(MV_ERROR_CANCELLED) to stop it. Returns the scene
  // it built (one reference), or nullptr for work whose result is a file.
  std::function<MvScene(const Progress& progress)> run;
  // A stage's fraction as a fraction of the whole work.
  std::function<double(const std::string& stage, double fraction)> overall;
  Progress user;  // the caller's progress function (throws to cancel); may be empty
};

// Starts `work` on its own thread, the device retained for it. Throws only before the thread starts.
MvJob start_job(MvDevice device, JobWork work);

// The caller's progress function as a Progress that throws ApiError(MV_ERROR_CANCELLED) when it returns false;
// `what` names the work in the message.
Progress user_progress(MvProgressMonitorFunction f, void* user, const char* what);

}  // namespace mv::capi

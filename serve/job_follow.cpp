#include <chrono>
#include <thread>

#include "job_run.h"
#include "serve_error.h"

namespace mv::serve {

void follow_job(MvJob j, const JobRun& run, double from, double to) {
  for (;;) {
    double f = 0;
    if (mvGetJobStatus(j, &f) >= MV_JOB_DONE) break;
    if (!run.report(mvGetJobMessage(j), from + (to - from) * f)) mvCancelJob(j);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const MvError e = mvWaitJob(j);
  const std::string message = mvGetJobMessage(j);
  mvReleaseJob(j);
  if (e == MV_ERROR_CANCELLED) throw JobStopped{};
  if (e != MV_ERROR_NONE) throw ServeError(message, e);
}

}  // namespace mv::serve

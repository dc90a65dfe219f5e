// One job as its runner sees it: the request, its files, and where progress goes. A runner returns when the
// result is written, throws ServeError (or another exception) with the failure's message, or JobStopped once
// the job is cancelled or past the server's job timeout. The pool (job_pool.cpp) turns that into the job's
// status.
#pragma once
#include <exception>
#include <functional>
#include <string>

#include "megavox/megavox.h"
#include "job_request.h"

namespace mv::serve {

// A std::exception so that the library's cleanups on the way out (temporary files and folders) run; the pool
// tells a stop from a failure by the job's cancel and timeout flags, not by what arrives.
struct JobStopped : std::exception {
  const char* what() const noexcept override { return "the job was stopped"; }
};

struct JobRun {
  const JobRequest& request;
  std::string input;         // the input file (under --data-dir, an upload, or a render's scene)
  std::string seeds, model;  // mask: the seed map and the .mvm, resolved under --data-dir ("" when none)
  std::string dir, result;   // the job's folder and the result file to write
  // Records the stage and its fraction done; false once the job should stop.
  std::function<bool(const std::string& stage, double fraction)> report;

  // report() for code that stops by unwinding: throws JobStopped.
  void progress(const std::string& stage, double fraction) const {
    if (!report(stage, fraction)) throw JobStopped{};
  }
};

// Follows a C API job until it ends, its stage and fraction (mapped onto [from, to] of the whole) fed to
// run.report, cancelling it once that says stop; releases it. Throws JobStopped once cancelled, ServeError
// with the job's code and message when it failed. serve/job_follow.cpp
void follow_job(MvJob job, const JobRun& run, double from = 0, double to = 1);

void run_build(MvDevice dev, const JobRun& run);   // serve/job_build.cpp
void run_render(MvDevice dev, const JobRun& run);  // serve/job_render.cpp
void run_points(MvDevice dev, const JobRun& run);  // serve/job_points.cpp
void run_mask(MvDevice dev, const JobRun& run);    // serve/job_mask.cpp
void run_open(MvDevice dev, const JobRun& run);    // serve/job_open.cpp

}  // namespace mv::serve

// An open job: a .mvx already under --data-dir becomes a scene for rays and renders without a build. The file
// is read and checked as mvOpenScene checks it (header, checksums, structure), so a damaged file fails here,
// named, rather than in a later query; it stays the user's: the job neither copies nor ever removes it.
#include "job_run.h"
#include "serve_error.h"

namespace mv::serve {

void run_open(MvDevice dev, const JobRun& run) {
  run.progress("open", 0);
  MvScene scene = mvOpenScene(dev, run.input.c_str());
  if (!scene) throw ServeError(mvGetDeviceLastErrorMessage(dev), mvGetDeviceError(dev));
  mvReleaseScene(scene);
  run.progress("open", 1);
}

}  // namespace mv::serve

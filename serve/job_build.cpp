// A build job: a mesh (or .vdb) to a voxel .mvx, as a C API job polled for its progress, the cancel flag and
// the timeout.
#include "job_run.h"
#include "serve_error.h"

namespace mv::serve {

void run_build(MvDevice dev, const JobRun& run) {
  const JobRequest& r = run.request;
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.format = r.format.c_str();
  a.resolution = r.resolution;
  if (r.cube) a.cube = *r.cube == 0 ? MV_CUBE_IN_CORE : *r.cube;  // the job's 0 is the CLI's --cube 0: in core
  a.voxelize = r.voxelize.c_str();
  a.gridOrigin = r.grid_origin.c_str();
  a.output = run.result.c_str();
  MvJob j = mvBuildSceneFromFileAsync(dev, run.input.c_str(), &a);
  if (!j) throw ServeError(mvGetDeviceLastErrorMessage(dev), mvGetDeviceError(dev));
  follow_job(j, run);
}

}  // namespace mv::serve

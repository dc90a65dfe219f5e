// A render job: a finished build's scene opened on the worker's context, drawn from a preset view or the
// client's camera (as the CLI's render takes them), written as PNG (temporary name, renamed).
#include <vector>

#include "job_run.h"
#include "serve_error.h"

namespace mv::serve {

namespace {

// A failed C API call on `dev` as the service's error, its code kept.
[[noreturn]] void fail(MvDevice dev) {
  const std::string message = mvGetDeviceLastErrorMessage(dev);
  throw ServeError(message, mvGetDeviceError(dev));
}

// The CLI's camera rule: the view frames the model at `fov`; `eye` replaces its position, `target` (else the
// model's centre, the view's target) and `up` go with it.
MvCamera job_camera(MvDevice dev, MvScene scene, const JobRequest& r) {
  MvCamera view;
  if (mvGetSceneViewCamera(scene, r.view.c_str(), r.fov, &view) != MV_ERROR_NONE) fail(dev);
  MvCamera c = view;
  for (int a = 0; a < 3; ++a) {
    c.eye[a] = r.eye ? (*r.eye)[a] : view.eye[a];
    c.target[a] = r.target ? (*r.target)[a] : view.target[a];
    c.up[a] = r.eye ? r.up[a] : view.up[a];
  }
  c.fov = r.fov;
  return c;
}

}  // namespace

void run_render(MvDevice dev, const JobRun& run) {
  const JobRequest& r = run.request;
  MvScene scene = mvOpenScene(dev, run.input.c_str());
  if (!scene) fail(dev);
  std::vector<uint8_t> rgba(size_t{r.width} * r.height * 4);
  MvError e = MV_ERROR_NONE;
  try {
    run.progress("render", 0);
    const MvCamera camera = job_camera(dev, scene, r);
    MvRenderArguments a;
    mvInitRenderArguments(&a);
    a.width = r.width;
    a.height = r.height;
    a.shading = r.shading.c_str();
    e = mvRenderScene(scene, &camera, &a, rgba.data(), 0);
  } catch (...) {
    mvReleaseScene(scene);
    throw;
  }
  mvReleaseScene(scene);
  if (e != MV_ERROR_NONE) fail(dev);
  run.progress("write", 0.9);
  if (mvWriteImage(run.result.c_str(), rgba.data(), r.width, r.height, 0) != MV_ERROR_NONE) fail(nullptr);
}

}  // namespace mv::serve

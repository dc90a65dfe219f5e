// A render job: a finished build's scene opened on the worker's context, drawn from a preset view or the
// client's camera (as the CLI's render takes them), written as PNG (temporary name, renamed).
#include <algorithm>
#include <vector>

#include "megavox/error.h"
#include "megavox/grid.h"
#include "megavox/render.h"
#include "job_run.h"

namespace mv::serve {

namespace {

// The CLI's camera rule: the view frames the model at `fov`; `eye` replaces its position, `target` (else the
// model's centre, the view's target) and `up` go with it.
MvCamera job_camera(MvDevice dev, MvScene scene, const JobRequest& r) {
  MvSceneInfo info;
  if (mvGetSceneInfo(scene, &info) != MV_ERROR_NONE) throw Error(mvGetDeviceLastErrorMessage(dev));
  Bounds bounds;
  for (int a = 0; a < 3; ++a) {
    bounds.lo[a] = info.lower[a];
    bounds.hi[a] = info.upper[a];
  }
  const Camera view = view_camera(bounds, r.view, r.fov);
  MvCamera c;
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
  if (!scene) throw Error(mvGetDeviceLastErrorMessage(dev));
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
  const std::string failure = e == MV_ERROR_NONE ? "" : mvGetDeviceLastErrorMessage(dev);
  mvReleaseScene(scene);
  if (e != MV_ERROR_NONE) throw CodedError(static_cast<ErrorCode>(e), failure);
  run.progress("write", 0.9);
  Image image;
  image.width = r.width;
  image.height = r.height;
  image.rgb.resize(size_t{r.width} * r.height * 3);
  for (size_t i = 0; i < size_t{r.width} * r.height; ++i) std::copy_n(&rgba[4 * i], 3, &image.rgb[3 * i]);
  write_png(run.result, image);
}

}  // namespace mv::serve

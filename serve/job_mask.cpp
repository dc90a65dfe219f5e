// A mask job: GrabCut of a photograph or range map from a box, a seed map and/or a model, with the library's
// masking as `megavox mask apply` runs it, written as a one-channel PNG (0 background, 255 foreground).
#include "job_run.h"
#include "serve_error.h"

namespace mv::serve {

void run_mask(MvDevice dev, const JobRun& run) {
  const JobRequest& r = run.request;
  MvMaskArguments a;
  mvInitMaskArguments(&a);
  if (r.rect) {
    a.hasRect = true;
    for (int i = 0; i < 4; ++i) a.rect[i] = (*r.rect)[i];
  }
  a.seeds = run.seeds.empty() ? nullptr : run.seeds.c_str();
  a.model = run.model.empty() ? nullptr : run.model.c_str();
  a.iterations = r.iterations;
  a.erode = r.erode;
  MvJob j = mvMaskImageFileAsync(dev, run.input.c_str(), run.result.c_str(), &a);
  if (!j) throw ServeError(mvGetDeviceLastErrorMessage(dev), mvGetDeviceError(dev));
  follow_job(j, run);
}

}  // namespace mv::serve

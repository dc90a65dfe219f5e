// `megavox bench mask`: the min-cut kernels against Boost's Boykov-Kolmogorov on GrabCut's first-iteration
// graphs (native size and upscaled 2x, 4- and 8-connected), and GrabCut masks from the database's boxes
// (error and time per image; OpenCV's cv::grabCut is the baseline where it is built in, see baselines.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/device.h"
#include "megavox/parallelism.h"
#include "megavox/min_cut.h"

namespace mv::bench {

struct CutRun {
  std::string image;
  uint32_t width = 0, height = 0, connectivity = 8;
  double megavox_seconds = 0, bk_seconds = 0;  // BK: its max-flow call alone, graph building not counted
  uint64_t value = 0;
  bool same_cut = false;  // value and source set equal to BK's
};

struct GrabCutRun {
  std::string image;
  uint32_t width = 0, height = 0, iterations = 0;
  double seconds = 0, error = 0, post_error = 0;
  // OpenCV's cv::grabCut from the same box and iterations, where it is built in (baseline::opencv()).
  bool opencv = false;
  double opencv_seconds = 0, opencv_error = 0;
};

// Cuts on the first `cut_images` images (sorted names) of `data`/images; GrabCut from boxes on the first
// `images` (0 = all). `solver` cuts both. `parallelism`, when given, sums the profiles of the timed calls
// (min_cut; mask_image), which need `dev` opened with profile = true.
std::vector<CutRun> bench_cuts(Device& dev, const std::string& data, uint32_t cut_images,
                               MinCutSolver solver = MinCutSolver::automatic, Parallelism* parallelism = nullptr);
std::vector<GrabCutRun> bench_grabcut(Device& dev, const std::string& data, uint32_t images, uint32_t iterations,
                                      MinCutSolver solver = MinCutSolver::automatic,
                                      Parallelism* parallelism = nullptr);

}  // namespace mv::bench

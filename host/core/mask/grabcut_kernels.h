// GrabCut's per-pixel kernels on a device (kernels/common/grabcut.h, grabcut_sums.h): the image's colours, labels
// and each pixel's components stay in device buffers from the first kernel to the last cut; the host reads back
// only the sums (a few hundred integers), the capacities a cut needs and the final labels.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "common/grabcut.h"
#include "gmm.h"
#include "megavox/device.h"
#include "megavox/raster.h"

namespace mv::mask {

// The host-side constants of one run (MV_GC_* in kernels/common/grabcut_math.h): exp/log tables and
// coefficients filled in; the caller sets beta, gamma, scale, lambda, mixtures and centres.
struct GrabCutConsts {
  std::vector<double> v;
  GrabCutConsts();
  void set_mixture(int side, const std::array<Gaussian, kComponents>& g);  // side 0 background, 1 foreground
  void set_centre(int side, int k, const double (&c)[3]);
};

class GrabCutKernels {
 public:
  // Uploads the image and the start labels (Label values) and packs the colours.
  GrabCutKernels(Device& dev, const RasterImage& image, const std::vector<uint8_t>& labels);

  uint32_t width() const { return w_; }
  uint32_t height() const { return h_; }
  uint64_t pixels() const { return n_; }

  void upload_consts(const GrabCutConsts& c);
  // Sum of squared colour differences over the 8-neighbour pairs (each once).
  uint64_t beta_sum();
  // Sum over every pixel's 8 edges of round(w * 2^20); keeps the weights (each pair's once) for edges().
  uint64_t smooth_sum();
  // The smoothness capacities of the last smooth_sum's weights at the constants' scale (grid_graph.h's layout).
  void edges(std::vector<uint32_t>& out);
  // Data terms and components (own_side_only: labelled pixels' own-side components only, no terms); returns
  // the terms' sum in units of 2^-20 (0 with own_side_only).
  uint64_t data(bool own_side_only);
  // Terminal capacities of the last data terms at the constants' scale.
  void terminals(std::vector<uint32_t>& source, std::vector<uint32_t>& sink);
  // Moments per side (0 background, 1 foreground) and component of the labelled pixels.
  std::array<Moments, 2> moments();
  // One Lloyd step with the constants' centres (centres[s] per side): each labelled pixel to its nearest centre
  // (its component), and per side and centre: count and colour sums.
  std::array<std::array<std::array<uint64_t, 4>, kComponents>, 2> kmeans(const uint32_t (&centres)[2]);
  // k-means++ seeding steps for the sides whose bit is set in `sides` (1 background, 2 foreground). mode 0:
  // d2 = 1 for the side's pixels; 1: squared distance to `colour`; 2: least of that and the old d2. Returns
  // each side's total of d2 (scan).
  std::array<uint64_t, 2> seed_d2(uint32_t mode, uint32_t sides, const uint32_t (&colour)[2]);
  // The pixel whose running sum of d2 first passes pick, per side in `sides`, and its colour.
  std::array<uint32_t, 2> seed_find(uint32_t sides, const uint64_t (&pick)[2], uint32_t (&colour)[2]);
  // New probable labels from a cut's source side; returns how many changed.
  uint64_t update_labels(const std::vector<uint8_t>& source_side);

  std::vector<uint8_t> labels() const;
  std::vector<uint32_t> colours() const;
  std::vector<uint32_t> components() const;  // bits 0-7 background, 8-15 foreground component
  std::vector<double> terms() const;         // source, sink per pixel
  void set_components(const std::vector<uint32_t>& comp);  // tests

 private:
  MvGrabCutParams params() const;
  uint32_t sum_groups() const;
  uint32_t pixel_groups() const;
  std::vector<uint64_t> run_sums(KernelId id, std::initializer_list<const Buffer*> buffers, MvGrabCutParams p,
                                 uint32_t channels);
  Device& dev_;
  uint32_t w_, h_;
  uint64_t n_;
  std::vector<uint8_t> side_bytes_;
  Buffer samples_, colour_, labels_, comp_, consts_, terms_, q_, edges_, weights_, sums_, side_, d2_[2], scan_[2], found_;
};

}  // namespace mv::mask

// Gaussian mixtures of colours for GrabCut: 5 full-covariance components in 3-D, fitted in double from integer
// moments the device sums (kernels/common/grabcut_sums.h), so every run on every device gets the same mixture
// bits; the kernels evaluate them (kernels/common/grabcut_math.h). k-means (k-means++ seeding from a fixed-seed
// splitmix64, 10 Lloyd iterations) initializes them, as OpenCV's grabCut does with its random generator.
#pragma once
#include <array>
#include <cstdint>

namespace mv::mask {

inline constexpr int kComponents = 5;

// One side's moments per component: count, sums of z_a, sums of z_a z_b (00 01 02 11 12 22) over its pixels.
using Moments = std::array<std::array<uint64_t, 10>, kComponents>;

struct Gaussian {
  double weight = 0;       // 0: no pixel; the component takes no part
  double mean[3] = {};
  double inverse[9] = {};  // row major
  double energy = 0;       // -log(weight / sqrt(det)): a pixel's energy is this plus half its Mahalanobis distance
};

// The maximum-likelihood fit per component (OpenCV's: a singular covariance gets 0.01 added to its diagonal).
std::array<Gaussian, kComponents> fit_mixture(const Moments& m);

// splitmix64: a fixed sequence, so k-means++ draws the same centres everywhere (std distributions are not).
struct SplitMix {
  uint64_t s = 0x9e3779b97f4a7c15ull;
  double unit() {  // [0, 1) from the top 53 bits
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
};

}  // namespace mv::mask

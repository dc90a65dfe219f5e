// Gaussian mixtures of colours for GrabCut: 5 full-covariance components in 3-D, learned in double in a fixed
// order, so every run on every machine gets the same mixture bits. Initialized by k-means (k-means++ seeding
// from a fixed-seed splitmix64, 10 Lloyd iterations), as OpenCV's grabCut does with its random generator.
#pragma once
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cstdint>
#include <vector>

namespace mv::mask {

using Colour = std::array<double, 3>;

class Gmm {
 public:
  static constexpr int kComponents = 5;

  // Learns from the samples with their component labels (0..4); a component without samples gets weight 0.
  void learn(const std::vector<Colour>& samples, const std::vector<uint8_t>& component);
  // The component of highest weighted density (the lowest index among equals).
  int component_of(const Colour& z) const;
  // The mixture density (without the (2 pi)^-3/2 factor, which cancels between two mixtures; OpenCV's form)
  // and component_of(), from one evaluation of the components.
  struct Fit {
    double density;
    int component;
  };
  Fit fit(const Colour& z) const;

 private:
  double component_density(int k, const Colour& z) const;
  struct Gaussian {
    double weight = 0, det = 1;
    double factor = 0;  // weight / sqrt(det), the density's constant
    Colour mean{};
    double inverse[9] = {};
  };
  std::array<Gaussian, kComponents> g_{};
};

// f(i) for i in [0, n) on the host's threads. Each call writes only its own outputs, so the result does not
// depend on the threads; sums stay serial, in index order.
template <class F>
void for_each_sample(size_t n, const F& f) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) f(i);
  });
}

// Component labels of k-means over the samples (k = 5; fewer distinct samples leave components empty).
std::vector<uint8_t> kmeans_components(const std::vector<Colour>& samples);

}  // namespace mv::mask

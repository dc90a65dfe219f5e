#include "gmm.h"

#include <cmath>
#include <limits>

namespace mv::mask {

std::array<Gaussian, kComponents> fit_mixture(const Moments& m) {
  std::array<Gaussian, kComponents> out{};
  double total = 0;
  for (const auto& k : m) total += static_cast<double>(k[0]);
  for (int k = 0; k < kComponents; ++k) {
    const double count = static_cast<double>(m[k][0]);
    if (count == 0) continue;
    Gaussian& g = out[k];
    g.weight = count / total;
    static constexpr int kProd[3][3] = {{4, 5, 6}, {5, 7, 8}, {6, 8, 9}};
    double c[9];
    for (int a = 0; a < 3; ++a) g.mean[a] = static_cast<double>(m[k][1 + a]) / count;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        c[3 * a + b] = static_cast<double>(m[k][kProd[a][b]]) / count - g.mean[a] * g.mean[b];
    auto det3 = [](const double* x) {
      return x[0] * (x[4] * x[8] - x[5] * x[7]) - x[1] * (x[3] * x[8] - x[5] * x[6]) + x[2] * (x[3] * x[7] - x[4] * x[6]);
    };
    double det = det3(c);
    if (det <= std::numeric_limits<double>::epsilon()) {  // singular (flat colour, grey images): OpenCV's fix
      c[0] += 0.01, c[4] += 0.01, c[8] += 0.01;
      det = det3(c);
    }
    g.energy = -std::log(g.weight / std::sqrt(det));
    g.inverse[0] = (c[4] * c[8] - c[5] * c[7]) / det;
    g.inverse[1] = (c[2] * c[7] - c[1] * c[8]) / det;
    g.inverse[2] = (c[1] * c[5] - c[2] * c[4]) / det;
    g.inverse[3] = (c[5] * c[6] - c[3] * c[8]) / det;
    g.inverse[4] = (c[0] * c[8] - c[2] * c[6]) / det;
    g.inverse[5] = (c[2] * c[3] - c[0] * c[5]) / det;
    g.inverse[6] = (c[3] * c[7] - c[4] * c[6]) / det;
    g.inverse[7] = (c[1] * c[6] - c[0] * c[7]) / det;
    g.inverse[8] = (c[0] * c[4] - c[1] * c[3]) / det;
  }
  return out;
}

}  // namespace mv::mask

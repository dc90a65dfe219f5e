#include "omicron_representatives_host.h"

namespace mv::points {

namespace {

// Twice the squared distance of a point from its cell's centre, from the code's low cell_bits bits (the
// point's place inside the cell, interleaved x, y, z): per axis the offset 2 * local + 1 - side.
int64_t centre_distance(uint64_t code, uint32_t cell_bits) {
  const uint32_t per_axis = cell_bits / 3;
  const int64_t side = int64_t{1} << per_axis;
  int64_t local[3] = {0, 0, 0};
  for (uint32_t bit = 0; bit < per_axis; ++bit)
    for (int axis = 0; axis < 3; ++axis) local[axis] |= static_cast<int64_t>((code >> (3 * bit + axis)) & 1) << bit;
  int64_t sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int64_t offset = 2 * local[axis] + 1 - side;
    sum += offset * offset;
  }
  return sum;
}

}  // namespace

std::vector<uint32_t> representatives_on_host(std::span<const uint64_t> codes, uint32_t cell_bits, uint32_t cap) {
  // The nearest point of each cell: cells are runs of equal code >> cell_bits in the sorted codes.
  std::vector<uint32_t> nearest;
  int64_t best = 0;
  for (size_t i = 0; i < codes.size(); ++i) {
    const int64_t d = centre_distance(codes[i], cell_bits);
    if (i == 0 || (codes[i] >> cell_bits) != (codes[i - 1] >> cell_bits)) {
      nearest.push_back(static_cast<uint32_t>(i));
      best = d;
    } else if (d < best) {
      nearest.back() = static_cast<uint32_t>(i);
      best = d;
    }
  }
  const uint64_t n = nearest.size();
  if (n <= cap) return nearest;
  std::vector<uint32_t> chosen;
  chosen.reserve(cap);
  for (uint64_t j = 0; j < n; ++j)
    if ((j + 1) * cap / n > j * cap / n) chosen.push_back(nearest[j]);
  return chosen;
}

}  // namespace mv::points

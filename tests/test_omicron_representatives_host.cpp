// The host's choice of one long parent's representatives (the device path's way round a loop cap) against the
// plain reference, on random clouds and the edges: one cell, every point its own cell, ties, cap 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "points/omicron_representatives_host.h"
#include "points_reference.h"

namespace {

std::vector<uint32_t> reference_of(const std::vector<uint64_t>& codes, uint32_t cell_bits, uint32_t cap) {
  const std::vector<uint32_t> one{0, static_cast<uint32_t>(codes.size())};
  return mv::ref::representatives(codes, one, cell_bits, cap);
}

TEST(RepresentativesOnHost, MatchTheReferenceOnRandomParents) {
  std::mt19937_64 rng(58);
  for (int trial = 0; trial < 60; ++trial) {
    const uint32_t cell_bits = 3 * (1 + trial % 6);
    const uint32_t cap = 1 + static_cast<uint32_t>(rng() % 300);
    const size_t n = 1 + rng() % 20000;
    // Codes inside one parent: a few cells' worth of bits above cell_bits, so cells hold many points.
    const uint64_t span = uint64_t{1} << (cell_bits + 1 + trial % 9);
    std::vector<uint64_t> codes(n);
    for (auto& c : codes) c = rng() % span;
    std::sort(codes.begin(), codes.end());
    EXPECT_EQ(mv::points::representatives_on_host(codes, cell_bits, cap), reference_of(codes, cell_bits, cap))
        << "trial " << trial;
  }
}

TEST(RepresentativesOnHost, MatchTheReferenceOnEdges) {
  const std::vector<std::vector<uint64_t>> clouds = {
      {5},                                // one point
      {7, 7, 7, 7},                       // ties: the first nearest point wins
      {0, 1, 2, 3, 4, 5, 6, 7},           // one cell of 8 codes
      {0, 8, 16, 24, 32, 40, 48, 56, 64}  // every point its own cell
  };
  for (const auto& codes : clouds)
    for (uint32_t cap : {1u, 2u, 3u, 100u}) {
      EXPECT_EQ(mv::points::representatives_on_host(codes, 3, cap), reference_of(codes, 3, cap));
      EXPECT_EQ(mv::points::representatives_on_host(codes, 0, cap), reference_of(codes, 0, cap));
    }
}

}  // namespace

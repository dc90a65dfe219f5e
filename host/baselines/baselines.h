// Baselines the benchmarks compare megavox against: libraries a user would pick instead (Boost.Sort's,
// ips4o's and Highway's vqsort sorts, Embree's triangle ray tracing, OpenCV's GrabCut). They live in their own target (megavox_baselines), linked
// only into the CLI, so the core library and the tests never depend on them. Whether each is built in is
// decided at configure time (CMake option MEGAVOX_BASELINES and whether the package is installed); a
// benchmark asks here and, when one is missing, prints missing_note() instead of a figure.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mv::baseline {

struct Baseline {
  const char* name;     // what the benchmark column is called
  const char* package;  // the Debian package that brings it
  bool built_in;        // compiled into this build
};

Baseline boost_sort();
Baseline ips4o();
Baseline vqsort();
Baseline embree();
Baseline opencv();

// One line for a benchmark whose baseline is missing: what, which package brings it, how to build it in.
std::string missing_note(const Baseline& b);

// (key, value) records as a C++ user would sort them.
struct Pair32 {
  uint32_t key, value;
};
struct Pair64 {
  uint64_t key;
  uint32_t value;
};

// boost::sort::block_indirect_sort by key on all threads. Returns false (and leaves the data) when not built in.
bool block_indirect_sort(std::span<Pair32> pairs);
bool block_indirect_sort(std::span<Pair64> pairs);

// ips4o::parallel::sort by key (Debian's ips4o runs on OpenMP threads, all of them). Returns false when not built in.
bool ips4o_parallel_sort(std::span<Pair32> pairs);
bool ips4o_parallel_sort(std::span<Pair64> pairs);

// vqsort (Highway's hwy::Sorter, one thread) of plain keys, ascending. It sorts keys, not records with a
// payload, so (key, value) records go in packed: 32-bit keys as key << 32 | value in a uint64_t, 64-bit keys
// as a 128-bit key (hi = key, lo = value). Whole-word comparison then orders equal keys by value, which for
// values = input index is exactly the stable order (hwy's K64V64 would compare the key alone, and vqsort is
// not stable). Returns false when not built in.
struct alignas(16) U128 {
  uint64_t lo, hi;  // hwy::uint128_t's layout
};
bool vqsort(std::span<uint32_t> keys);
bool vqsort(std::span<uint64_t> keys);
bool vqsort(std::span<U128> keys);

// Embree 3 over triangles (xyz float positions, 3 indices each): builds the scene, then traces one primary
// ray per pixel (origin `eye`, direction dir0 + x * dx + y * dy), rows over all threads, best of `repeats`:
// single rays (rtcIntersect1), then packets of 16 rays over 4 x 4 pixels (rtcIntersect16).
struct EmbreeFrame {
  uint32_t width = 0, height = 0;
  float eye[3] = {0, 0, 0};
  float dir0[3] = {0, 0, 0}, dx[3] = {0, 0, 0}, dy[3] = {0, 0, 0};
};
struct EmbreeResult {
  double build_seconds = 0, trace_seconds = 0;  // scene build; best pass over all pixels
  double packet_seconds = 0;                    // the same with rtcIntersect16
  std::vector<uint8_t> hit;                     // per pixel, rows top to bottom (single rays)
  uint64_t packet_mismatches = 0;               // pixels where the packets' hit flag differs from the single ray's
};
// Throws mv::Error when Embree is not built in (check embree().built_in first) or cannot start.
EmbreeResult embree_primary_hits(std::span<const float> positions, std::span<const uint32_t> indices,
                                 const EmbreeFrame& frame, uint32_t repeats);

// OpenCV's cv::grabCut (GC_INIT_WITH_RECT, `iterations`) on 8-bit RGB pixels, rows top to bottom. The mask
// is 255 where OpenCV labels (probable) foreground, else 0; seconds is the cv::grabCut call alone. Throws
// mv::Error when OpenCV is not built in (check opencv().built_in first).
struct GrabCutBox {
  uint32_t x = 0, y = 0, w = 0, h = 0;
};
struct OpenCvMask {
  std::vector<uint8_t> mask;
  double seconds = 0;
};
OpenCvMask opencv_grabcut(std::span<const uint8_t> rgb, uint32_t width, uint32_t height, const GrabCutBox& box,
                          uint32_t iterations);

}  // namespace mv::baseline

// `megavox bench points`: `megavox points build` (build_points_file: read, sort, build, write) timed on a point
// cloud beside its floor, the time megavox's own reader takes to decode every point and nothing else; and a
// cloud of any size sampled from a triangle mesh's surface, for clouds larger than the ones at hand.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "plain_read.h"
#include "megavox/device.h"
#include "megavox/parallelism.h"
#include "megavox/point_build.h"

namespace mv::bench {

// PotreeConverter 2's rate on this kind of machine as the issue quotes it (points per second): a quoted figure,
// not a measurement of this run (PotreeConverter is not in Debian, and nothing outside is reachable here).
inline constexpr double kPotreeQuotedPointsPerSecond = 2.85e6;

struct MeshSample {
  std::string mesh, path;
  uint64_t points = 0, triangles = 0, bytes = 0;
  uint64_t seed = 0;
  double area = 0;     // the surface's area, in the mesh's units squared
  double seconds = 0;  // reading the mesh, sampling and writing the file
};

// Samples `points` points from the surface of the triangle mesh `mesh` (io::open_mesh), area-weighted and
// deterministic for a `seed` (std::mt19937_64; a triangle by a cumulative area table, a point in it by uniform
// barycentric coordinates with the square-root rule), and writes them to `path` as a binary little-endian PLY:
// float x, y, z and uchar red, green, blue (the face normal's direction, n / 2 + 1/2), in streamed blocks (the
// file is never whole in memory). Throws mv::Error for a mesh without area or a file that cannot be written.
MeshSample sample_mesh_to_ply(const std::string& mesh, uint64_t points, const std::string& path, uint64_t seed = 1);

// Every point of `path` decoded by megavox's reader (io::open_points, then next() until the end) into one
// columns object cleared per batch: decoding, not storing.
struct ReadFloor {
  uint64_t points = 0;
  double seconds = 0;
};
ReadFloor read_floor(const std::string& path);
// The same reader appending every batch to one growing columns object, as build_points_file's read stage does
// (its time without freeing them): beside the floor it shows what storing the points adds to decoding them.
ReadFloor read_and_store(const std::string& path);

struct PointsBenchResult {
  std::string input;
  PointFileReport report;  // of the fastest build (by read + sort + build)
  Parallelism parallelism;  // of the same build, read to write (file reading and writing as io_seconds)
  PlainRead plain;         // the file read plainly (bench::plain_read)
  ReadFloor floor;         // the fastest of the repeats
  std::vector<double> floor_runs;
  ReadFloor stored;        // read_and_store, the fastest of the repeats
  std::vector<double> build_runs;  // read + sort + build of every build, in order (the first builds the kernels)
  double seconds = 0;              // the fastest run's read + sort + build
  double seconds_with_write = 0;   // the same run with its write
  double points_per_second = 0;    // points in / seconds
  double floor_points_per_second = 0;
  double ratio_to_read_floor = 0;  // seconds / floor.seconds
  double vs_potree_quoted = 0;     // points_per_second / kPotreeQuotedPointsPerSecond
  uint64_t peak_rss_bytes = 0;     // this process's peak while this cloud ran (getrusage), device runtime included
  bool peak_rss_reset = false;     // the peak was reset before this cloud (/proc/self/clear_refs); else the
                                   // process's peak so far
};

// Builds a synthetic cloud of about a million points (random, with RGB) on `dev` and drops it, so that
// compiling the point kernels is in none of the figures that follow; returns its seconds.
double warm_up_point_build(Device& dev, const PointBuildOptions& build = {});

// Plain read, `repeats` read floors and reads with storing, then `repeats` builds of `input` to a scratch .mvx (removed); the
// figures are the best of each. The parallelism profile needs `dev` opened with profile = true.
PointsBenchResult run_points_bench(Device& dev, const std::string& input, int repeats,
                                   const PointBuildOptions& build = {}, uint64_t memory = 0);

}  // namespace mv::bench

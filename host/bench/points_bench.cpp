#include "points_bench.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "peak_rss.h"
#include "scratch_dir.h"
#include "io/mesh_source.h"
#include "io/point_source.h"
#include "megavox/error.h"
#include "stopwatch.h"

namespace mv::bench {

namespace {

// Uniform in [0, 1) from the generator's 64 bits (53 of them), the same on every standard library
// (std::uniform_real_distribution's algorithm is the library's own).
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

void put_le32(uint8_t* out, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  out[0] = uint8_t(u);
  out[1] = uint8_t(u >> 8);
  out[2] = uint8_t(u >> 16);
  out[3] = uint8_t(u >> 24);
}

uint8_t normal_channel(double n) { return uint8_t(std::clamp(std::lround((n * 0.5 + 0.5) * 255.0), 0L, 255L)); }

}  // namespace

MeshSample sample_mesh_to_ply(const std::string& mesh, uint64_t points, const std::string& path, uint64_t seed) {
  const auto t0 = Clock::now();
  MeshSample s;
  s.mesh = mesh;
  s.path = path;
  s.points = points;
  s.seed = seed;

  std::unique_ptr<io::MeshSource> src = io::open_mesh(mesh);
  const std::span<const float> pos = src->positions();
  std::vector<uint32_t> tris, batch;
  while (src->next_triangles(batch, size_t{1} << 20)) tris.insert(tris.end(), batch.begin(), batch.end());
  const uint64_t vertices = pos.size() / 3;
  s.triangles = tris.size() / 3;

  // The cumulative area table and each face's colour, from its normal.
  std::vector<double> cumulative(s.triangles);
  std::vector<std::array<uint8_t, 3>> colour(s.triangles);
  double total = 0;
  for (uint64_t t = 0; t < s.triangles; ++t) {
    double v[3][3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = tris[3 * t + k];
      if (i >= vertices)
        throw Error(mesh + ": triangle " + std::to_string(t) + " names vertex " + std::to_string(i) + " of " +
                    std::to_string(vertices));
      for (int a = 0; a < 3; ++a) v[k][a] = pos[3 * size_t(i) + a];
    }
    const double e1[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
    const double e2[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    total += 0.5 * len;
    cumulative[t] = total;
    for (int a = 0; a < 3; ++a) colour[t][a] = normal_channel(len > 0 ? n[a] / len : 0);
  }
  if (!(total > 0) || !std::isfinite(total))
    throw Error(mesh + ": no surface to sample (" + std::to_string(s.triangles) + " triangles, total area " +
                std::to_string(total) + ")");
  s.area = total;

  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw Error(path + ": cannot be written: " + std::strerror(errno));
  const std::string header = "ply\nformat binary_little_endian 1.0\ncomment megavox bench points: " +
                             std::to_string(points) + " points sampled from " +
                             std::filesystem::path(mesh).filename().string() + " (area-weighted, seed " +
                             std::to_string(seed) + "; colour from the face normal)\nelement vertex " +
                             std::to_string(points) +
                             "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
                             "property uchar green\nproperty uchar blue\nend_header\n";
  bool ok = std::fwrite(header.data(), 1, header.size(), f) == header.size();

  constexpr size_t kRecord = 15;
  constexpr uint64_t kBlock = uint64_t{1} << 20;  // points per write: 15 MiB
  std::vector<uint8_t> buf(kBlock * kRecord);
  std::mt19937_64 rng(seed);
  for (uint64_t done = 0; ok && done < points;) {
    const uint64_t n = std::min(kBlock, points - done);
    uint8_t* out = buf.data();
    for (uint64_t p = 0; p < n; ++p, out += kRecord) {
      const double u = unit(rng) * total;
      const uint64_t t = std::min<uint64_t>(
          std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin(), s.triangles - 1);
      const double r = std::sqrt(unit(rng)), r2 = unit(rng);
      const double w[3] = {1 - r, r * (1 - r2), r * r2};
      for (int a = 0; a < 3; ++a) {
        double c = 0;
        for (int k = 0; k < 3; ++k) c += w[k] * pos[3 * size_t(tris[3 * t + k]) + a];
        put_le32(out + 4 * a, float(c));
      }
      std::memcpy(out + 12, colour[t].data(), 3);
    }
    ok = std::fwrite(buf.data(), 1, n * kRecord, f) == n * kRecord;
    done += n;
  }
  const int err = ok ? 0 : errno;
  if (std::fclose(f) != 0 && ok) ok = false;
  if (!ok) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    throw Error(path + ": write failed" + (err ? std::string(": ") + std::strerror(err) : std::string()) +
                " (a sampled cloud takes 15 bytes a point; set TMPDIR to a folder with room)");
  }
  s.bytes = header.size() + points * kRecord;
  s.seconds = since(t0);
  return s;
}

ReadFloor read_floor(const std::string& path) {
  const auto t0 = Clock::now();
  std::unique_ptr<io::PointSource> src = io::open_points(path);  // build_points_file's reader and options
  PointColumns batch;
  ReadFloor r;
  while (src->next(batch, size_t{1} << 20)) {  // build_points_file's batch
    r.points += batch.size();
    batch.clear();
  }
  src.reset();
  r.seconds = since(t0);
  return r;
}

double warm_up_point_build(Device& dev, const PointBuildOptions& build) {
  const auto t0 = Clock::now();
  const uint64_t n = (uint64_t{1} << 20) + 4096;  // past one builder step (prefix_points)
  PointColumns c;
  c.xyz.resize(3 * n);
  c.rgb.resize(3 * n);
  std::mt19937_64 rng(7);
  for (auto& v : c.xyz) v = int32_t(rng() >> 44);  // 20 bits
  for (auto& v : c.rgb) v = uint16_t(rng() >> 56);
  PointCloudInfo info;
  info.format = "bench points warm-up";
  info.points = n;
  info.attributes = kPointRgb;
  build_point_hierarchy(dev, std::move(c), info, build);
  return since(t0);
}

ReadFloor read_and_store(const std::string& path) {
  const auto t0 = Clock::now();
  std::unique_ptr<io::PointSource> src = io::open_points(path);
  PointColumns cloud;
  while (src->next(cloud, size_t{1} << 20)) {
  }
  src.reset();
  ReadFloor r{cloud.size(), since(t0)};
  return r;  // the columns are freed after the clock stopped
}

PointsBenchResult run_points_bench(Device& dev, const std::string& input, int repeats, const PointBuildOptions& build,
                                   uint64_t memory) {
  repeats = std::max(repeats, 1);
  PointsBenchResult r;
  r.input = input;
  r.peak_rss_reset = reset_peak_rss();
  r.plain = plain_read(input);  // first: it also warms the page cache for what follows
  for (int rep = 0; rep < repeats; ++rep) {
    const ReadFloor f = read_floor(input);
    r.floor_runs.push_back(f.seconds);
    if (rep == 0 || f.seconds < r.floor.seconds) r.floor = f;
  }
  for (int rep = 0; rep < repeats; ++rep) {
    const ReadFloor f = read_and_store(input);
    if (rep == 0 || f.seconds < r.stored.seconds) r.stored = f;
  }

  ScratchDir scratch;
  PointFileOptions o;
  o.input = input;
  o.output = scratch.file("bench.mvx");
  o.build = build;
  o.memory = memory;
  for (int rep = 0; rep < repeats; ++rep) {
    std::filesystem::remove(o.output);  // each run writes the file anew, as a user's build does
    ParallelismMeter meter(dev);
    meter.start();
    PointFileReport report = build_points_file(dev, o);
    Parallelism parallelism = meter.stop(report.read_seconds + report.write_seconds);
    const double seconds = report.read_seconds + report.sort_seconds + report.build_seconds;
    r.build_runs.push_back(seconds);
    if (rep == 0 || seconds < r.seconds) {
      r.seconds = seconds;
      r.report = std::move(report);
      r.parallelism = std::move(parallelism);
    }
  }
  r.report.output.clear();  // a scratch file, removed
  r.peak_rss_bytes = peak_rss_bytes();

  r.seconds_with_write = r.seconds + r.report.write_seconds;
  const double points = double(r.report.points_in);
  if (r.seconds > 0) r.points_per_second = points / r.seconds;
  if (r.floor.seconds > 0) {
    r.floor_points_per_second = double(r.floor.points) / r.floor.seconds;
    r.ratio_to_read_floor = r.seconds / r.floor.seconds;
  }
  r.vs_potree_quoted = r.points_per_second / kPotreeQuotedPointsPerSecond;
  return r;
}

}  // namespace mv::bench

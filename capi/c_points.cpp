// The C API: point-cloud builds (a PLY or LAS cloud to a .mvx point hierarchy or a 3D Tiles folder), as a
// call and as a job.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include "job.h"
#include "megavox/point_build.h"
#include "option_words.h"

namespace mv::capi {

namespace {

struct PointBuild {
  PointFileOptions options;
  Progress user;
};

PointBuild point_build(MvDevice device, const char* input, const char* output, const MvPointBuildArguments* args) {
  require(device, "points build: no device");
  require(input && *input, "points build: no input path");
  require(output && *output, "points build: no output path");
  PointBuild b;
  b.options.input = input;
  b.options.output = output;
  b.options.memory = device->host_memory;
  if (!args) return b;
  constexpr size_t kFirstSize = offsetof(MvPointBuildArguments, tilesVersion);  // before the tiles' options
  require(args->byteSize == sizeof(MvPointBuildArguments) || args->byteSize == kFirstSize,
          "points build: MvPointBuildArguments.byteSize is wrong (call mvInitPointBuildArguments)");
  b.options.format = parse_point_output(args->format ? args->format : "mvx");
  b.options.build.depth = args->depth;
  if (args->maxNodePoints) b.options.build.max_node_points = args->maxNodePoints;
  if (args->byteSize == sizeof(MvPointBuildArguments)) {
    const std::string version = args->tilesVersion ? args->tilesVersion : "1.1";
    require(version == "1.1" || version == "1.0", ("points build: tilesVersion '" + version + "': 1.1 or 1.0").c_str());
    b.options.tiles_minor_version = version == "1.0" ? 0 : 1;
    if (args->crs) b.options.crs = args->crs;
    if (args->bounds) {
      std::array<double, 6> box;
      std::copy(args->bounds, args->bounds + 6, box.begin());
      for (int a = 0; a < 3; ++a)
        require(std::isfinite(box[a]) && std::isfinite(box[3 + a]) && box[a] <= box[3 + a],
                "points build: bounds must be finite, each min at most its max");
      b.options.bounds = box;
    }
  }
  b.user = user_progress(args->progress, args->progressUserPtr, "points build");
  return b;
}

// Reading and sorting, building, writing: about their shares of a build's time.
double points_overall(const std::string& stage, double f) {
  if (stage == "read") return 0.3 * f;
  if (stage == "build") return 0.3 + 0.5 * f;
  if (stage == "write") return 0.8 + 0.2 * f;
  return 0;
}

void run_point_build(MvDevice device, const PointFileOptions& options, const Progress& progress) {
  std::lock_guard<std::recursive_mutex> g(device->lock);
  build_points_file(*device->device, options, progress);
}

}  // namespace

}  // namespace mv::capi

using namespace mv::capi;

extern "C" {

void mvInitPointBuildArguments(MvPointBuildArguments* args) {
  if (!args) return;
  *args = MvPointBuildArguments{};
  args->byteSize = sizeof(MvPointBuildArguments);
  args->format = "mvx";
  args->tilesVersion = "1.1";
  args->maxNodePoints = mv::PointBuildOptions{}.max_node_points;
}

MvError mvBuildPointsFile(MvDevice device, const char* input, const char* output, const MvPointBuildArguments* args) {
  return guard(device, [&] {
    const PointBuild b = point_build(device, input, output, args);
    run_point_build(device, b.options, b.user);
  });
}

void mvInitPointArrays(MvPointArrays* points) {
  if (!points) return;
  *points = MvPointArrays{};
  points->byteSize = sizeof(MvPointArrays);
}

MvError mvBuildPointsFromMemory(MvDevice device, const MvPointArrays* points, const char* output,
                                const MvPointBuildArguments* args) {
  return guard(device, [&] {
    require(points, "points build: points is NULL (call mvInitPointArrays)");
    require(points->byteSize == sizeof(MvPointArrays), "points build: MvPointArrays.byteSize is wrong (call mvInitPointArrays)");
    require(!points->xyz32 != !points->xyz64, "points build: give exactly one of xyz32 and xyz64");
    require(points->count <= SIZE_MAX / 3, "points build: the point count overflows");
    const size_t n = points->count;
    mv::PointArrays arrays;
    if (points->xyz32) arrays.xyz32 = {points->xyz32, 3 * n};
    else arrays.xyz64 = {points->xyz64, 3 * n};
    if (points->rgb) arrays.rgb = {points->rgb, 3 * n};
    if (points->intensity) arrays.intensity = {points->intensity, n};
    if (points->extra) {
      require(points->extraBytes > 0 && points->extraBytes <= 65535, "points build: extraBytes is not 1 to 65535");
      require(n <= SIZE_MAX / points->extraBytes, "points build: the extra bytes' size overflows");
      arrays.extra = {points->extra, size_t{points->extraBytes} * n};
      arrays.extra_bytes = points->extraBytes;
    }
    PointBuild b = point_build(device, "points in memory", output, args);
    b.options.arrays = &arrays;
    run_point_build(device, b.options, b.user);
  });
}

MvJob mvBuildPointsFileAsync(MvDevice device, const char* input, const char* output,
                             const MvPointBuildArguments* args) {
  MvJob job = nullptr;
  guard(device, [&] {
    PointBuild b = point_build(device, input, output, args);
    JobWork work;
    work.run = [device, options = std::move(b.options)](const mv::Progress& progress) -> MvScene {
      run_point_build(device, options, progress);
      return nullptr;
    };
    work.overall = points_overall;
    work.user = std::move(b.user);
    job = start_job(device, std::move(work));
  });
  return job;
}

}  // extern "C"

// A point-cloud job: a PLY or LAS cloud to a .mvx point hierarchy, or to a 3D Tiles archive (.3tz), with the
// library's builder as `megavox points build` runs it.
#include <filesystem>

#include "megavox/point_build.h"
#include "device_access.h"
#include "job_run.h"
#include "tiles_archive.h"

namespace mv::serve {

void run_points(MvDevice dev, const JobRun& run) {
  const JobRequest& r = run.request;
  const bool tiles = r.format == "3dtiles";
  PointFileOptions o;
  o.input = run.input;
  // a tileset is a folder: built beside the result, archived into it, then removed
  o.output = tiles ? (std::filesystem::path(run.dir) / "tiles").string() : run.result;
  o.format = r.format;
  o.build.depth = r.depth;
  o.build.max_node_points = r.max_node_points;
  // the builder's stages as parts of the whole: reading and sorting, building, writing (and archiving)
  const auto share = [&](const std::string& stage, double f) {
    const double at = stage == "read" ? 0.3 * f : stage == "build" ? 0.3 + 0.5 * f : 0.8 + (tiles ? 0.1 : 0.2) * f;
    run.progress(stage, at);
  };
  on_device(dev, [&](Device& device, uint64_t host_memory) {
    o.memory = host_memory;
    build_points_file(device, o, share);
  });
  if (!tiles) return;
  struct RemoveFolder {  // whether the archive is written, fails or the job stops here
    std::string path;
    ~RemoveFolder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  } folder{o.output};
  run.progress("archive", 0.9);
  write_3tz(o.output, run.result);
}

}  // namespace mv::serve

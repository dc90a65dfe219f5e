// A point-cloud job: a PLY or LAS cloud to a .mvx point hierarchy, or to a 3D Tiles archive (.3tz), as a C API
// job (the library's builder as `megavox points build` runs it).
#include <filesystem>

#include "job_run.h"
#include "serve_error.h"
#include "tiles_archive.h"

namespace mv::serve {

void run_points(MvDevice dev, const JobRun& run) {
  const JobRequest& r = run.request;
  const bool tiles = r.format == "3dtiles";
  // a tileset is a folder: built beside the result, archived into it, then removed
  const std::string output = tiles ? (std::filesystem::path(run.dir) / "tiles").string() : run.result;
  MvPointBuildArguments a;
  mvInitPointBuildArguments(&a);
  a.format = r.format.c_str();
  a.depth = r.depth;
  a.maxNodePoints = r.max_node_points;
  a.tilesVersion = r.tiles_version.c_str();
  if (!r.crs.empty()) a.crs = r.crs.c_str();
  if (r.bounds) a.bounds = r.bounds->data();
  struct RemoveFolder {  // whether the archive is written, fails or the job stops on the way
    std::string path;
    ~RemoveFolder() {
      if (path.empty()) return;
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  } folder{tiles ? output : ""};
  MvJob j = mvBuildPointsFileAsync(dev, run.input.c_str(), output.c_str(), &a);
  if (!j) throw ServeError(mvGetDeviceLastErrorMessage(dev), mvGetDeviceError(dev));
  follow_job(j, run, 0, tiles ? 0.9 : 1);  // archiving is the rest of a tileset's
  if (!tiles) return;
  run.progress("archive", 0.9);
  write_3tz(output, run.result);
}

}  // namespace mv::serve

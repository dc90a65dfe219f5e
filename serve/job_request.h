// What a client asks `megavox serve` to do: a job's JSON body (or an upload's query parameters), checked
// field by field. Untrusted bytes: fuzz/fuzz_job_request.cpp runs this parser.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "megavox/megavox.h"

namespace mv::serve {

// open: a .mvx already under --data-dir as a scene for rays and renders, without a build.
enum class JobKind { build, render, points, mask, open };

struct JobRequest {
  JobKind kind = JobKind::build;
  std::string input;  // a file under --data-dir (relative); empty for an upload or a render of `scene`
  std::string scene;  // render: the id of a finished build or open job
  // build: format is svo, svdag, ussvdag or ssvdag; points: mvx or 3dtiles
  uint32_t resolution = 256;
  // Above this resolution a build runs out of core in cubes of this side; 0: in core; unset: the C API's and
  // the CLI's default.
  std::optional<uint32_t> cube;
  std::string format = "svdag", voxelize = "conservative", grid_origin = "center";
  // render: the CLI's picture size; a preset view, or a camera from `eye` (target and up as the CLI's defaults)
  uint32_t width = 1920, height = 1080;
  std::string view = "iso", shading = "shaded";
  std::optional<std::array<double, 3>> eye, target;
  std::array<double, 3> up = {0, 1, 0};
  double fov = MV_DEFAULT_FOV;
  // points: 0 picks the leaf level from the point count
  uint32_t depth = 0, max_node_points = 16384;
  // points as 3dtiles: 3D Tiles 1.1 or 1.0, and a CRS to place the tileset with (EPSG:N or WKT) over the input's
  std::string tiles_version = "1.1", crs;
  // points from LAS or LAZ: only the points in this box (world min x, y, z, max x, y, z)
  std::optional<std::array<double, 6>> bounds;
  // mask: at least one start (a box, a seed map under --data-dir, a .mvm model under --data-dir)
  std::optional<std::array<uint32_t, 4>> rect;  // x, y, w, h in pixels
  std::string seeds, model;
  uint32_t iterations = 5, erode = 2;
};

// Parses a job's JSON object. Throws ServeError (serve/serve_error.h) with a message for the client: malformed JSON (with where),
// an unknown key or one of another kind of job, a value of the wrong type or out of range, a job without
// what it needs (a mask without a start).
JobRequest parse_job_request(std::string_view json);

// The same fields from an upload's query parameters (numbers as text, lists as comma-separated numbers);
// `uploaded` is then the input.
JobRequest job_request_from_query(const std::multimap<std::string, std::string>& params);

std::string kind_name(JobKind k);

}  // namespace mv::serve

#include "job_request.h"

#include <cmath>
#include <initializer_list>

#include <nlohmann/json.hpp>

#include "serve_error.h"

namespace mv::serve {

namespace {

using nlohmann::json;

// Which kinds of job take a key: a key of another kind is refused rather than ignored, so a client's mistake
// (a "rect" on a build) is said instead of silently doing something else.
struct KeyKinds {
  const char* key;
  std::initializer_list<JobKind> kinds;
};
const KeyKinds kKeys[] = {
    {"input", {JobKind::build, JobKind::render, JobKind::points, JobKind::mask, JobKind::open}},
    {"scene", {JobKind::render}},
    {"resolution", {JobKind::build}},
    {"cube", {JobKind::build}},
    {"format", {JobKind::build, JobKind::points}},
    {"voxelize", {JobKind::build}},
    {"grid_origin", {JobKind::build}},
    {"width", {JobKind::render}},
    {"height", {JobKind::render}},
    {"view", {JobKind::render}},
    {"shading", {JobKind::render}},
    {"eye", {JobKind::render}},
    {"target", {JobKind::render}},
    {"up", {JobKind::render}},
    {"fov", {JobKind::render}},
    {"depth", {JobKind::points}},
    {"max_node_points", {JobKind::points}},
    {"tiles_version", {JobKind::points}},
    {"crs", {JobKind::points}},
    {"bounds", {JobKind::points}},
    {"rect", {JobKind::mask}},
    {"seeds", {JobKind::mask}},
    {"model", {JobKind::mask}},
    {"iterations", {JobKind::mask}},
    {"erode", {JobKind::mask}},
};

std::string quoted(const std::string& key) { return "\"" + key.substr(0, 64) + "\""; }

[[noreturn]] void refuse(const std::string& key, const std::string& what) { throw ServeError("job: " + quoted(key) + " " + what); }

std::string text(const json& j, const char* key) {
  if (!j.is_string()) refuse(key, "must be a string");
  return j.get<std::string>();
}

int64_t integer(const json& j, const char* key) {
  if (!j.is_number_integer() && !j.is_number_unsigned()) refuse(key, "must be an integer");
  return j.is_number_unsigned() ? int64_t(std::min<uint64_t>(j.get<uint64_t>(), INT64_MAX)) : j.get<int64_t>();
}

uint32_t number(const json& j, const char* key, uint32_t lo, uint32_t hi) {
  const int64_t v = integer(j, key);
  if (v < lo || v > hi) refuse(key, "must be from " + std::to_string(lo) + " to " + std::to_string(hi));
  return static_cast<uint32_t>(v);
}

double real(const json& j, const char* key) {
  if (!j.is_number()) refuse(key, "must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) refuse(key, "must be finite");
  return v;
}

std::string choice(const json& j, const char* key, std::initializer_list<const char*> choices) {
  const std::string v = text(j, key);
  std::string list;
  for (const char* c : choices) {
    if (v == c) return v;
    list += (list.empty() ? "" : ", ") + std::string(c);
  }
  refuse(key, "'" + v.substr(0, 64) + "': choose " + list);
}

std::array<double, 3> vec3(const json& j, const char* key) {
  if (!j.is_array() || j.size() != 3) refuse(key, "must be an array of three numbers [x, y, z]");
  std::array<double, 3> v{};
  for (size_t i = 0; i < 3; ++i) v[i] = real(j[i], key);
  return v;
}

// min x, y, z, then max x, y, z: finite, each min at most its max.
std::array<double, 6> box(const json& j) {
  if (!j.is_array() || j.size() != 6) refuse("bounds", "must be an array of six numbers [minx, miny, minz, maxx, maxy, maxz]");
  std::array<double, 6> b{};
  for (size_t i = 0; i < 6; ++i) b[i] = real(j[i], "bounds");
  for (size_t a = 0; a < 3; ++a)
    if (b[a] > b[3 + a]) refuse("bounds", "must give each minimum at most its maximum");
  return b;
}

// x, y, w, h in pixels; the largest image megavox reads has 2^28 pixels, so no side or corner lies past that.
std::array<uint32_t, 4> rect(const json& j) {
  if (!j.is_array() || j.size() != 4) refuse("rect", "must be an array of four integers [x, y, w, h]");
  std::array<uint32_t, 4> r{};
  for (size_t i = 0; i < 4; ++i) {
    const int64_t v = integer(j[i], "rect");
    if (v < (i < 2 ? 0 : 1) || v > (int64_t{1} << 28))
      refuse("rect", i < 2 ? "x and y must be from 0 to 268435456" : "w and h must be from 1 to 268435456");
    r[i] = static_cast<uint32_t>(v);
  }
  return r;
}

bool takes(const std::string& key, JobKind kind, bool& known) {
  for (const KeyKinds& k : kKeys)
    if (key == k.key) {
      known = true;
      for (JobKind t : k.kinds)
        if (t == kind) return true;
      return false;
    }
  known = false;
  return false;
}

std::string key_list(JobKind kind) {
  std::string list = "kind";
  for (const KeyKinds& k : kKeys)
    for (JobKind t : k.kinds)
      if (t == kind) list += std::string(", ") + k.key;
  return list;
}

// The camera as the CLI's render takes it: `eye` replaces the view; `target` (default the model's centre)
// and `up` go with it. A camera looking nowhere, or along its own up, has no picture.
void check_camera(const JobRequest& r, const json& j) {
  if (!r.eye) {
    if (j.contains("target") || j.contains("up")) throw ServeError("job: \"target\" and \"up\" go with \"eye\" (or use \"view\")");
    return;
  }
  const auto& u = r.up;
  if (u[0] == 0 && u[1] == 0 && u[2] == 0) throw ServeError("job: \"up\" must not be [0, 0, 0]");
  if (r.target) {
    const std::array<double, 3> d = {(*r.target)[0] - (*r.eye)[0], (*r.target)[1] - (*r.eye)[1], (*r.target)[2] - (*r.eye)[2]};
    const double len = std::hypot(d[0], d[1], d[2]);
    if (!(len > 0)) throw ServeError("job: \"eye\" and \"target\" must differ");
    const std::array<double, 3> c = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
    if (!(std::hypot(c[0], c[1], c[2]) > 1e-9 * len * std::hypot(u[0], u[1], u[2])))
      throw ServeError("job: \"up\" must not point along the line from \"eye\" to \"target\"");
  }
}

JobKind parse_kind(const json& j) {
  if (!j.contains("kind")) throw ServeError("job: \"kind\" is missing (build, render, points, mask or open)");
  const std::string k = choice(j.at("kind"), "kind", {"build", "render", "points", "mask", "open"});
  return k == "build"    ? JobKind::build
         : k == "render" ? JobKind::render
         : k == "points" ? JobKind::points
         : k == "open"   ? JobKind::open
                         : JobKind::mask;
}

JobRequest from_object(const json& j) {
  if (!j.is_object()) throw ServeError("job: the body must be a JSON object");
  JobRequest r;
  r.kind = parse_kind(j);
  if (r.kind == JobKind::points) r.format = "mvx";
  for (const auto& [key, v] : j.items()) {
    if (key == "kind") continue;
    bool known = false;
    if (!takes(key, r.kind, known))
      throw ServeError("job: " + std::string(known ? (r.kind == JobKind::open ? "an " : "a ") + kind_name(r.kind) + " job takes no " : "unknown key ") + quoted(key) +
                  " (keys: " + key_list(r.kind) + ")");
    if (key == "input") r.input = text(v, "input");
    else if (key == "scene") r.scene = text(v, "scene");
    else if (key == "resolution") {
      r.resolution = number(v, "resolution", 2, 1u << 21);
      if (r.resolution & (r.resolution - 1)) refuse("resolution", "must be a power of two");
    } else if (key == "cube") {
      const uint32_t cube = number(v, "cube", 0, 1u << 21);
      r.cube = cube;
      if (cube && (cube < 8 || (cube & (cube - 1)))) refuse("cube", "must be 0 (always in core) or a power of two from 8");
    } else if (key == "format") {
      r.format = r.kind == JobKind::points ? choice(v, "format", {"mvx", "3dtiles"})
                                           : choice(v, "format", {"svo", "svdag", "ussvdag", "ssvdag"});
    } else if (key == "voxelize") r.voxelize = choice(v, "voxelize", {"conservative", "thin"});
    else if (key == "grid_origin") r.grid_origin = choice(v, "grid_origin", {"center", "min"});
    else if (key == "width") r.width = number(v, "width", 1, 8192);
    else if (key == "height") r.height = number(v, "height", 1, 8192);
    else if (key == "view") r.view = choice(v, "view", {"iso", "front", "back", "left", "right", "top"});
    else if (key == "shading") r.shading = choice(v, "shading", {"shaded", "normal", "depth", "level", "heat", "colour"});
    else if (key == "eye") r.eye = vec3(v, "eye");
    else if (key == "target") r.target = vec3(v, "target");
    else if (key == "up") r.up = vec3(v, "up");
    else if (key == "fov") {
      r.fov = real(v, "fov");
      if (!(r.fov > 0 && r.fov < 180)) refuse("fov", "must lie between 0 and 180 degrees");
    } else if (key == "depth") r.depth = number(v, "depth", 0, 21);
    else if (key == "max_node_points") r.max_node_points = number(v, "max_node_points", 1, 1u << 24);
    else if (key == "tiles_version") r.tiles_version = choice(v, "tiles_version", {"1.1", "1.0"});
    else if (key == "crs") {
      r.crs = text(v, "crs");
      if (r.crs.empty() || r.crs.size() > 65536) refuse("crs", "must be EPSG:N or a WKT of at most 64 KiB");
    } else if (key == "bounds") r.bounds = box(v);
    else if (key == "rect") r.rect = rect(v);
    else if (key == "seeds") r.seeds = text(v, "seeds");
    else if (key == "model") r.model = text(v, "model");
    else if (key == "iterations") r.iterations = number(v, "iterations", 1, 100);
    else if (key == "erode") r.erode = number(v, "erode", 0, 32);
  }
  if (!r.input.empty() && !r.scene.empty()) throw ServeError("job: give \"input\" or \"scene\", not both");
  if (r.kind == JobKind::build && r.format == "ssvdag" && r.resolution < 8)
    throw ServeError("job: format ssvdag needs a resolution of at least 8");
  if (r.kind == JobKind::points && r.format != "3dtiles" && (r.tiles_version != "1.1" || !r.crs.empty()))
    throw ServeError("job: \"tiles_version\" and \"crs\" apply to \"format\": \"3dtiles\" only");
  if (r.kind == JobKind::render) check_camera(r, j);
  if (r.kind == JobKind::open && r.input.empty())
    throw ServeError("job: an open job needs \"input\": a .mvx under the data folder");
  if (r.kind == JobKind::mask && !r.rect && r.seeds.empty() && r.model.empty())
    throw ServeError("job: a mask job needs a start: \"rect\" [x, y, w, h], \"seeds\" (a seed map) or \"model\" (a .mvm)");
  return r;
}

// A query value as the JSON the body would hold: integers, numbers, and comma-separated lists of them.
json query_value(const std::string& key, const std::string& value) {
  static const char* const integers[] = {"resolution", "cube", "width", "height", "depth", "max_node_points", "iterations", "erode"};
  static const char* const lists[] = {"eye", "target", "up", "rect", "bounds"};
  const auto whole = [&](const std::string& s) {
    if (s.empty() || s.size() > 10 || s.find_first_not_of("0123456789") != std::string::npos)
      throw ServeError("job: " + quoted(key) + " must be " + (key == "rect" ? "four integers X,Y,W,H" : "an integer"));
    return json(std::stoull(s));
  };
  const auto decimal = [&](const std::string& s) {
    size_t used = 0;
    double d = 0;
    try {
      d = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (s.empty() || used != s.size() || !std::isfinite(d)) throw ServeError("job: " + quoted(key) + " must hold numbers");
    return json(d);
  };
  for (const char* k : integers)
    if (key == k) return whole(value);
  if (key == "fov") return decimal(value);
  for (const char* k : lists)
    if (key == k) {
      json a = json::array();
      size_t start = 0;
      for (size_t i = 0; i <= value.size() && a.size() < 7; ++i)
        if (i == value.size() || value[i] == ',') {
          const std::string part = value.substr(start, i - start);
          a.push_back(key == "rect" ? whole(part) : decimal(part));
          start = i + 1;
        }
      return a;
    }
  return value;
}

}  // namespace

std::string kind_name(JobKind k) {
  switch (k) {
    case JobKind::build: return "build";
    case JobKind::render: return "render";
    case JobKind::points: return "points";
    case JobKind::mask: return "mask";
    case JobKind::open: return "open";
  }
  return "build";
}

JobRequest parse_job_request(std::string_view body) {
  json j;
  try {
    j = json::parse(body.begin(), body.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number past 64 bits (fuzz_job_request)
    throw ServeError(std::string("malformed JSON: ") + e.what());
  }
  return from_object(j);
}

JobRequest job_request_from_query(const std::multimap<std::string, std::string>& params) {
  json j = json::object();
  for (const auto& [key, value] : params) {
    if (j.contains(key)) throw ServeError("job: query parameter " + quoted(key) + " given twice");
    if (key == "name") continue;  // the uploaded file's name (kept for its extension), read by the server
    j[key] = query_value(key, value);
  }
  if (j.value("kind", "") == "open") throw ServeError("job: an open job names a .mvx under the data folder in a JSON job");
  if (j.contains("input") || j.contains("scene")) throw ServeError("job: an upload is the input; \"input\" and \"scene\" go in a JSON job");
  return from_object(j);
}

}  // namespace mv::serve

#include "serve/job_request.h"

#include <nlohmann/json.hpp>

#include "megavox/error.h"

namespace mv::serve {

namespace {

using nlohmann::json;

constexpr const char* kKeys = "kind, input, scene, resolution, format, voxelize, grid_origin, width, height, view, shading";

std::string text(const json& j, const char* key) {
  if (!j.is_string()) throw Error(std::string("job: \"") + key + "\" must be a string");
  return j.get<std::string>();
}

uint32_t number(const json& j, const char* key, uint32_t lo, uint32_t hi) {
  if (!j.is_number_integer() && !j.is_number_unsigned()) throw Error(std::string("job: \"") + key + "\" must be an integer");
  const int64_t v = j.is_number_unsigned() ? int64_t(std::min<uint64_t>(j.get<uint64_t>(), INT64_MAX)) : j.get<int64_t>();
  if (v < lo || v > hi)
    throw Error(std::string("job: \"") + key + "\" must be from " + std::to_string(lo) + " to " + std::to_string(hi));
  return static_cast<uint32_t>(v);
}

std::string choice(const json& j, const char* key, std::initializer_list<const char*> choices) {
  const std::string v = text(j, key);
  std::string list;
  for (const char* c : choices) {
    if (v == c) return v;
    list += (list.empty() ? "" : ", ") + std::string(c);
  }
  throw Error(std::string("job: \"") + key + "\" '" + v.substr(0, 64) + "': choose " + list);
}

JobRequest from_object(const json& j) {
  if (!j.is_object()) throw Error("job: the body must be a JSON object");
  JobRequest r;
  if (!j.contains("kind")) throw Error("job: \"kind\" is missing (build or render)");
  r.kind = choice(j.at("kind"), "kind", {"build", "render"}) == "build" ? JobKind::build : JobKind::render;
  for (const auto& [key, v] : j.items()) {
    if (key == "kind") continue;
    else if (key == "input") r.input = text(v, "input");
    else if (key == "scene") r.scene = text(v, "scene");
    else if (key == "resolution") {
      r.resolution = number(v, "resolution", 2, 1u << 21);
      if (r.resolution & (r.resolution - 1)) throw Error("job: \"resolution\" must be a power of two");
    } else if (key == "format") r.format = choice(v, "format", {"svo", "svdag", "ussvdag", "ssvdag"});
    else if (key == "voxelize") r.voxelize = choice(v, "voxelize", {"conservative", "thin"});
    else if (key == "grid_origin") r.grid_origin = choice(v, "grid_origin", {"center", "min"});
    else if (key == "width") r.width = number(v, "width", 1, 8192);
    else if (key == "height") r.height = number(v, "height", 1, 8192);
    else if (key == "view") r.view = choice(v, "view", {"iso", "front", "back", "left", "right", "top"});
    else if (key == "shading") r.shading = choice(v, "shading", {"shaded", "normal", "depth", "level", "heat"});
    else throw Error("job: unknown key \"" + key.substr(0, 64) + "\" (keys: " + kKeys + ")");
  }
  if (r.kind == JobKind::build && !r.scene.empty()) throw Error("job: \"scene\" names what a render job draws; a build takes \"input\"");
  if (!r.input.empty() && !r.scene.empty()) throw Error("job: give \"input\" or \"scene\", not both");
  if (r.kind == JobKind::build && r.format == "ssvdag" && r.resolution < 8)
    throw Error("job: format ssvdag needs a resolution of at least 8");
  return r;
}

}  // namespace

std::string kind_name(JobKind k) { return k == JobKind::build ? "build" : "render"; }

JobRequest parse_job_request(std::string_view body) {
  json j;
  try {
    j = json::parse(body.begin(), body.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number past 64 bits (fuzz_job_request)
    throw Error(std::string("malformed JSON: ") + e.what());
  }
  return from_object(j);
}

JobRequest job_request_from_query(const std::multimap<std::string, std::string>& params) {
  json j = json::object();
  for (const auto& [key, value] : params) {
    if (j.contains(key)) throw Error("job: query parameter \"" + key.substr(0, 64) + "\" given twice");
    if (key == "resolution" || key == "width" || key == "height") {
      if (value.empty() || value.size() > 10 || value.find_first_not_of("0123456789") != std::string::npos)
        throw Error("job: \"" + key + "\" must be an integer");
      j[key] = std::stoull(value);
    } else if (key == "name") {
      continue;  // the uploaded file's name (kept for its extension), read by the server
    } else {
      j[key] = value;
    }
  }
  if (j.contains("input") || j.contains("scene")) throw Error("job: an upload is the input; \"input\" and \"scene\" go in a JSON job");
  return from_object(j);
}

}  // namespace mv::serve

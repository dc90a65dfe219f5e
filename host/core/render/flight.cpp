// Camera flights (megavox/render.h): {"fov": F, "frames": [{"eye": [x,y,z], "target": [x,y,z], "up": [x,y,z]}, …]}.
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "io/file_ops.h"
#include "megavox/error.h"
#include "megavox/render.h"

namespace mv {

namespace {

constexpr size_t kMaxFrames = 1000000;

void read_vec3(const nlohmann::json& frame, const char* key, double out[3], const std::string& where, bool required) {
  auto it = frame.find(key);
  if (it == frame.end()) {
    if (required) throw Error(where + ": no \"" + key + "\" (three numbers in model units)");
    return;
  }
  if (!it->is_array() || it->size() != 3) throw Error(where + ": \"" + key + "\" must be an array of three numbers");
  for (int a = 0; a < 3; ++a) {
    const nlohmann::json& v = (*it)[a];
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw Error(where + ": \"" + key + "\" must be an array of three finite numbers");
    out[a] = v.get<double>();
  }
}

}  // namespace

std::vector<Camera> parse_flight(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(name + ": not JSON: " + e.what());
  }
  if (!j.is_object()) throw Error(name + ": a flight is a JSON object {\"fov\": F, \"frames\": [...]}");
  double fov = 40;
  if (auto it = j.find("fov"); it != j.end()) {
    if (!it->is_number() || !(it->get<double>() > 0 && it->get<double>() < 180))
      throw Error(name + ": \"fov\" must be a number of degrees between 0 and 180");
    fov = it->get<double>();
  }
  auto frames = j.find("frames");
  if (frames == j.end() || !frames->is_array() || frames->empty())
    throw Error(name + ": \"frames\" must be a non-empty array of {\"eye\", \"target\", \"up\"} objects");
  if (frames->size() > kMaxFrames) throw Error(name + ": more than " + std::to_string(kMaxFrames) + " frames");
  std::vector<Camera> out;
  out.reserve(frames->size());
  for (size_t i = 0; i < frames->size(); ++i) {
    const std::string where = name + ": frame " + std::to_string(i);
    const nlohmann::json& f = (*frames)[i];
    if (!f.is_object()) throw Error(where + ": not an object");
    Camera c;
    c.fov = fov;
    read_vec3(f, "eye", c.eye, where, true);
    read_vec3(f, "target", c.target, where, true);
    read_vec3(f, "up", c.up, where, false);
    if (c.eye[0] == c.target[0] && c.eye[1] == c.target[1] && c.eye[2] == c.target[2])
      throw Error(where + ": the eye and the target are the same point");
    out.push_back(c);
  }
  return out;
}

std::vector<Camera> read_flight(const std::string& path) {
  const std::vector<char> bytes = io::read_whole_file(path);
  return parse_flight(std::string(bytes.begin(), bytes.end()), path);
}

}  // namespace mv

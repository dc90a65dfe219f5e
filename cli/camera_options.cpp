#include "camera_options.h"

#include "cli_common.h"
#include "megavox/error.h"

namespace mv::cli {

void add_camera_options(CLI::App& cmd, CameraArgs& a, const std::string& up_default, const std::string& json_help) {
  cmd.add_option("--width", a.width, "Image width in pixels")->capture_default_str();
  cmd.add_option("--height", a.height, "Image height in pixels")->capture_default_str();
  cmd.add_option("--view", a.view, "Preset camera framing the model: front, back, left, right, top or iso")
      ->capture_default_str();
  cmd.add_option("--eye", a.eye, "Camera position X,Y,Z in model units (replaces --view)");
  cmd.add_option("--target", a.target, "Point looked at X,Y,Z in model units (default: the model's centre)");
  cmd.add_option("--up", a.up, "Up direction X,Y,Z, or x, y or z for an axis (default: " + up_default + ")");
  cmd.add_option("--fov", a.fov, "Vertical field of view in degrees")->capture_default_str();
  cmd.add_flag("--json", a.json, json_help);
  cmd.add_flag("-q,--quiet", a.quiet, "Print nothing but errors");
}

CameraVectors camera_vectors(const CameraArgs& a) {
  auto vec = [](const std::string& text, const char* what) {
    std::array<double, 3> v{};
    parse_vec3(text, what, v.data());
    return v;
  };
  CameraVectors c;
  if (!a.eye.empty()) c.eye = vec(a.eye, "--eye");
  if (!a.target.empty()) c.target = vec(a.target, "--target");
  if (a.up == "x" || a.up == "y" || a.up == "z") {
    c.up = std::array<double, 3>{};
    (*c.up)[a.up[0] - 'x'] = 1;
  } else if (!a.up.empty()) {
    try {
      c.up = vec(a.up, "--up");
    } catch (const CodedError&) {
      throw CodedError(ErrorCode::invalid_argument,
                       "--up wants X,Y,Z (three numbers separated by commas) or an axis, x, y or z; got '" + a.up + "'");
    }
  }
  if (c.target && !c.eye) throw CodedError(ErrorCode::invalid_argument, "--target needs --eye (or use --view)");
  if (c.up && (*c.up)[0] == 0 && (*c.up)[1] == 0 && (*c.up)[2] == 0)
    throw CodedError(ErrorCode::invalid_argument, "--up must not be 0,0,0");
  return c;
}

}  // namespace mv::cli

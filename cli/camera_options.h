// The options both render verbs (`render`, `points render`) share, registered once so that their names, forms
// and defaults agree: the picture's size, the camera, and what is printed.
#pragma once
#include <CLI/CLI.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace mv::cli {

struct CameraArgs {
  uint32_t width = 1920, height = 1080;
  std::string view = "iso";
  std::string eye, target, up;  // as given; empty: not given
  double fov = 40;
  bool json = false, quiet = false;
};

// --width --height --view --eye --target --up --fov --json -q/--quiet on `cmd`, into `a`. `up_default` says
// what an unset --up means for this verb; `json_help` what --json prints.
void add_camera_options(CLI::App& cmd, CameraArgs& a, const std::string& up_default, const std::string& json_help);

// The camera vectors given on the command line, in model units; unset where the option was not given.
struct CameraVectors {
  std::optional<std::array<double, 3>> eye, target, up;
};
// Parses --eye, --target (which needs --eye) and --up: X,Y,Z, or x, y or z for that axis. Throws naming the option.
CameraVectors camera_vectors(const CameraArgs& a);

}  // namespace mv::cli

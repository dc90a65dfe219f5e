// The options `megavox build` and `megavox bench build` share, so the benchmark runs the build a user runs.
#pragma once
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "megavox/build.h"

namespace mv::cli {

struct BuildArgs {
  std::string input, resolution, format = "svdag", grid, grid_origin = "center", bounds, voxelize = "conservative";
  std::string memory, attributes = "auto", page_order = "subtree";
  uint32_t colour_bits = 24;
  uint32_t page_words = kMvxPageWords;
  uint32_t cube = kDefaultCube;
};

// The input and every build option but the output: --resolution, --grid, --cube, --format, --grid-origin,
// --bounds, --voxelize, --attributes, --colour-bits, --memory, --page-order, --page-words (--device-memory is global).
void add_build_options(CLI::App& cmd, BuildArgs& a);

// Those options as `megavox build` arguments (the input first), for a build run as another process.
std::vector<std::string> build_argv(const BuildArgs& a);

// The build those options ask for (throws mv::Error on a bad resolution, bounds or size).
BuildOptions build_options(const BuildArgs& a);

// A build's report as `build --json` prints it.
nlohmann::json report_json(const BuildReport& r);

}  // namespace mv::cli

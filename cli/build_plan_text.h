// A build's plan as `megavox build` states it before the heavy work: lines on stderr, and the "plan" object of
// `build --json`.
#pragma once
#include <nlohmann/json.hpp>

#include "megavox/build.h"

namespace mv::cli {

// The grid, in core or in cubes, the estimates and any warnings, on stderr.
void print_plan(const BuildPlan& p);

nlohmann::json plan_json(const BuildPlan& p);

}  // namespace mv::cli

// The parallelism profile (megavox/parallelism.h) as the CLI reports it: one JSON object, or lines on stderr.
#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "megavox/parallelism.h"

namespace mv::cli {

// {"wall_seconds", "device_seconds", "host_seconds", "wait_seconds", "io_seconds", "narrow_seconds",
//  "narrow_share" (narrow / device seconds), "width", "kernels": [{"kernel", "launches", "work_items", "seconds",
//  "narrow_seconds"}, ...] (most device time first)}
nlohmann::json parallelism_json(const Parallelism& p);

// The same for a person, on stderr: the totals on one line headed by `stage`, then one line per kernel.
void print_parallelism(const std::string& stage, const Parallelism& p);

}  // namespace mv::cli

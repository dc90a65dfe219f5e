// What a client asks `megavox serve` to do: a job's JSON body (or an upload's query parameters), checked
// field by field. Untrusted bytes: fuzz/fuzz_job_request.cpp runs this parser.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace mv::serve {

enum class JobKind { build, render };

struct JobRequest {
  JobKind kind = JobKind::build;
  std::string input;  // a file under --data-dir (relative); empty for an upload or a render of `scene`
  std::string scene;  // render: the id of a finished build job
  // build
  uint32_t resolution = 256;
  std::string format = "svdag", voxelize = "conservative", grid_origin = "center";
  // render
  uint32_t width = 1280, height = 720;
  std::string view = "iso", shading = "shaded";
};

// Parses a job's JSON object. Throws mv::Error with a message for the client: malformed JSON (with where),
// an unknown key, a value of the wrong type or out of range, a build without an input.
JobRequest parse_job_request(std::string_view json);

// The same fields from an upload's query parameters (numbers as text); `uploaded` is then the input.
JobRequest job_request_from_query(const std::multimap<std::string, std::string>& params);

std::string kind_name(JobKind k);

}  // namespace mv::serve

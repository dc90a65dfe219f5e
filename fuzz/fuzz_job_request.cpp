// parse_job_request (serve/job_request.h): the JSON body of a `megavox serve` job, straight from the client.
// A parsed request must hold only values the server can run: a known kind, a power-of-two resolution, a
// picture size in range, and a build that names no scene.
#include <string_view>

#include "fuzz_support.h"
#include "megavox/error.h"
#include "serve/job_request.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const mv::serve::JobRequest r = mv::serve::parse_job_request(std::string_view(reinterpret_cast<const char*>(data), size));
    MV_FUZZ_CHECK(r.kind == mv::serve::JobKind::build || r.kind == mv::serve::JobKind::render);
    MV_FUZZ_CHECK(r.resolution >= 2 && r.resolution <= (1u << 21) && (r.resolution & (r.resolution - 1)) == 0);
    MV_FUZZ_CHECK(r.width >= 1 && r.width <= 8192 && r.height >= 1 && r.height <= 8192);
    MV_FUZZ_CHECK(r.kind == mv::serve::JobKind::render || r.scene.empty());
    MV_FUZZ_CHECK(r.input.empty() || r.scene.empty());
  } catch (const mv::Error&) {
  }
  return 0;
}

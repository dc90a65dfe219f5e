// parse_job_request (serve/job_request.h): the JSON body of a `megavox serve` job, straight from the client.
// A parsed request must hold only values the server can run: a known kind, a power-of-two resolution and
// cube, a picture size in range, a camera that looks somewhere, a mask with a start, and no key of another
// kind of job.
#include <cmath>
#include <string_view>

#include "fuzz_support.h"
#include "serve_error.h"
#include "job_request.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using mv::serve::JobKind;
  try {
    const mv::serve::JobRequest r = mv::serve::parse_job_request(std::string_view(reinterpret_cast<const char*>(data), size));
    MV_FUZZ_CHECK(r.kind == JobKind::build || r.kind == JobKind::render || r.kind == JobKind::points || r.kind == JobKind::mask);
    MV_FUZZ_CHECK(r.resolution >= 2 && r.resolution <= (1u << 21) && (r.resolution & (r.resolution - 1)) == 0);
    const uint32_t cube = r.cube.value_or(0);  // unset: the shared default
    MV_FUZZ_CHECK(cube == 0 || (cube >= 8 && cube <= (1u << 21) && (cube & (cube - 1)) == 0));
    MV_FUZZ_CHECK(r.width >= 1 && r.width <= 8192 && r.height >= 1 && r.height <= 8192);
    MV_FUZZ_CHECK(r.kind == JobKind::render || r.scene.empty());
    MV_FUZZ_CHECK(r.input.empty() || r.scene.empty());
    MV_FUZZ_CHECK(r.fov > 0 && r.fov < 180);
    MV_FUZZ_CHECK(!r.target || r.eye);
    if (r.eye) MV_FUZZ_CHECK(std::isfinite((*r.eye)[0]) && std::isfinite((*r.eye)[1]) && std::isfinite((*r.eye)[2]));
    MV_FUZZ_CHECK(r.kind == JobKind::points ? r.format == "mvx" || r.format == "3dtiles" : r.format != "3dtiles");
    MV_FUZZ_CHECK(r.depth <= 21 && r.max_node_points >= 1);
    MV_FUZZ_CHECK(r.kind != JobKind::mask || r.rect || !r.seeds.empty() || !r.model.empty());
    MV_FUZZ_CHECK(r.kind == JobKind::mask || (!r.rect && r.seeds.empty() && r.model.empty()));
    if (r.rect) MV_FUZZ_CHECK((*r.rect)[2] >= 1 && (*r.rect)[3] >= 1);
    MV_FUZZ_CHECK(r.iterations >= 1 && r.iterations <= 100 && r.erode <= 32);
  } catch (const mv::serve::ServeError&) {
  }
  return 0;
}

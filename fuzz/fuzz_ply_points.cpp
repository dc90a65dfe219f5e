// open_points on PLY point clouds (seeds: fuzz/corpus/fuzz_ply_points/).
#include "points_target.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return mv::fuzz::read_points(data, size, ".ply");
}

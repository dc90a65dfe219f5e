// open_points on LAS files (seeds: fuzz/corpus/fuzz_las/).
#include "points_target.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return mv::fuzz::read_points(data, size, ".las");
}

// open_points on LAZ files: the LASzip record, the chunk table, both compressors' chunks, every item coder
// (seeds: PDAL's small LAZ files from ../shared/data/pointcloud_laz, copied in by scripts/fuzz.sh).
#include "points_target.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return mv::fuzz::read_points(data, size, ".laz");
}

// Plain C++ reference of the splat kernels (kernels/common/splat.h): each pixel keeps the smallest (depth key,
// point index) pair of the points whose splat covers it, which is what the two atomic-min passes compute.
#pragma once
#include <cstdint>
#include <vector>

#include "points/point_frame.h"

namespace mv::ref {

// depth and index per pixel (MV_SPLAT_EMPTY where no splat reached) for all of frame.cells.
void splat_reference(const points::SplatFrame& frame, std::vector<uint32_t>& depth, std::vector<uint32_t>& index);

}  // namespace mv::ref

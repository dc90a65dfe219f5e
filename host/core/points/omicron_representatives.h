// The representatives of OMiCroN's inner nodes on the device (kernels: kernels/points/omicron.cl, bodies in
// kernels/common/omicron.h, over the segmented primitives of megavox/segmented.h): the kept points of every
// parent of a level in a few dispatches spread over candidates and cells, whatever size each parent has. The
// plain C++ reference is ref::representatives (host/ref/points_reference.h); the tests compare the two.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "megavox/device.h"

namespace mv::points {

// Representatives of many parents at one level. Parent g's candidates are codes[bounds[g], bounds[g + 1]), in
// Morton order; its sub-grid cells are the codes >> cell_bits. Of each occupied cell the candidate nearest the
// cell's centre (the first of equals) is kept; of more than `cap` cells, cap spread along the Morton order.
// Returns the kept candidates' positions in codes, parent by parent; offsets (groups + 1 values) delimits them.
struct RepSelection {
  std::vector<uint32_t> positions;
  std::vector<uint64_t> offsets;
};
RepSelection select_representatives(Device& dev, std::span<const uint64_t> codes, std::span<const uint32_t> bounds,
                                    uint32_t cell_bits, uint32_t cap);

}  // namespace mv::points

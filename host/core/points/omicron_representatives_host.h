// The representatives of one parent chosen on the host: the device path's way round a parent longer than the
// device's loop cap (lavapipe ends a loop after 65535 iterations). The same rule as the kernel's
// (kernels/common/omicron.h): per cell of 2^cell_bits codes, the point nearest the cell's centre (the first on a
// tie); of n cells, every cell when n <= cap, else the cells j where floor((j + 1) cap / n) > floor(j cap / n).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace mv::points {

// Positions in `codes` (one parent's sorted Morton codes) of its representatives, in order.
std::vector<uint32_t> representatives_on_host(std::span<const uint64_t> codes, uint32_t cell_bits, uint32_t cap);

}  // namespace mv::points

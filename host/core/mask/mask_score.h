// Scoring masks against the GrabCut database's ground truth (docs/masks.md): the error is misclassified
// labelled pixels over labelled pixels (truth 0 or 255; the 128 band of mixed pixels excluded), and a box start
// is the truth's foreground bounding box enlarged by 5 % of its width / height per side (rounded), clipped to
// the image, inset by one pixel on every side where it would cover the whole image.
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/mask.h"

namespace mv::mask {

// Throws mv::Error when the truth has no foreground pixel.
MaskBox box_from_truth(const std::vector<uint16_t>& truth, uint32_t width, uint32_t height);

// `mask` 0 / non-zero against `truth` 0 / 255 (other values unlabelled).
double mask_error(const std::vector<uint8_t>& mask, const std::vector<uint16_t>& truth);

}  // namespace mv::mask

// OpenCL entry points of mask post-processing (bodies: common/mask_post.h). 2-D launches, a pixel per item.
#include "common/mask_post.h"

__kernel void mask_median5(__global uint* src, __global uint* dst, MvMaskPostParams p) {
  mv_mask_median5(src, dst, p, MV_GLOBAL_ID_D(0), MV_GLOBAL_ID_D(1));
}

__kernel void mask_erode(__global uint* src, __global uint* dst, MvMaskPostParams p) {
  mv_mask_erode(src, dst, p, MV_GLOBAL_ID_D(0), MV_GLOBAL_ID_D(1));
}

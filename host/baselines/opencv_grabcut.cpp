// The GrabCut baseline: OpenCV's cv::grabCut from a box (present only when built in).
#include <chrono>

#include "baselines.h"
#include "megavox/error.h"
#include "timing.h"

#if MEGAVOX_HAVE_OPENCV
#include <opencv2/imgproc.hpp>
#endif

namespace mv::baseline {

#if MEGAVOX_HAVE_OPENCV
OpenCvMask opencv_grabcut(std::span<const uint8_t> rgb, uint32_t width, uint32_t height, const GrabCutBox& box,
                          uint32_t iterations) {
  if (rgb.size() != size_t{width} * height * 3) throw Error("bench mask: OpenCV's image is not 3 bytes per pixel");
  // OpenCV's images are BGR; GrabCut treats the channels alike, but the order is kept as OpenCV expects.
  cv::Mat img(int(height), int(width), CV_8UC3);
  for (size_t i = 0; i < size_t{width} * height; ++i) {
    uint8_t* p = img.data + i * 3;
    p[0] = rgb[i * 3 + 2], p[1] = rgb[i * 3 + 1], p[2] = rgb[i * 3];
  }
  cv::Mat mask, bgd, fgd;
  const cv::Rect rect(int(box.x), int(box.y), int(box.w), int(box.h));
  OpenCvMask out;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    cv::grabCut(img, mask, rect, bgd, fgd, int(iterations), cv::GC_INIT_WITH_RECT);
  } catch (const cv::Exception& e) {
    throw Error(std::string("bench mask: cv::grabCut failed: ") + e.what());
  }
  out.seconds = seconds_since(t0);
  out.mask.resize(size_t{width} * height);
  for (size_t i = 0; i < out.mask.size(); ++i) out.mask[i] = (mask.data[i] & 1) ? 255 : 0;  // GC_FGD, GC_PR_FGD
  return out;
}
#else
OpenCvMask opencv_grabcut(std::span<const uint8_t>, uint32_t, uint32_t, const GrabCutBox&, uint32_t) {
  throw Error(missing_note(opencv()));
}
#endif

}  // namespace mv::baseline

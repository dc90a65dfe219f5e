// The C API: pictures written to files (PNG or JPEG by the name), for callers that render with mvRenderScene.
#include <cstring>

#include "handles.h"
#include "io/output_path.h"
#include "megavox/render.h"

using namespace mv::capi;

extern "C" {

MvError mvWriteImage(const char* path, const uint8_t* rgba, uint32_t width, uint32_t height, size_t rowStride) {
  return guard(nullptr, [&] {
    require(path && *path, "mvWriteImage: no path");
    require(rgba, "mvWriteImage: rgba is NULL");
    require(width >= 1 && height >= 1 && width <= 65535 && height <= 65535,
            "mvWriteImage: width and height must be 1 to 65535");
    const size_t stride = rowStride ? rowStride : size_t{width} * 4;
    require(stride >= size_t{width} * 4, "mvWriteImage: rowStride is below width * 4");
    const std::string format = mv::io::format_of_extension(path) == "jpeg" ? "jpeg" : "png";
    const std::string target = mv::io::resolve_output({path, mv::io::OutputKind::kFile, format});
    mv::Image image;
    image.width = width;
    image.height = height;
    image.rgb.resize(size_t{width} * height * 3);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x)
        std::memcpy(&image.rgb[(size_t{y} * width + x) * 3], rgba + y * stride + size_t{x} * 4, 3);
    mv::write_image(target, image);
  });
}

}  // extern "C"

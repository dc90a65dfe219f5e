// JPEG output of a rendered image: the format a .jpg / .jpeg name asks for (write_image in megavox/image.h).
#include "atomic_file.h"
#include "file_ops.h"
#include "jpeg_encode.h"
#include "megavox/error.h"
#include "megavox/image.h"
#include "output_path.h"

namespace mv {

void write_image(const std::string& path, const Image& image) {
  if (io::format_of_extension(path) != "jpeg") return write_png(path, image);
  if (image.width == 0 || image.height == 0 || image.rgb.size() != size_t{image.width} * image.height * 3)
    throw Error("write_image: the image is empty or its size does not match its pixels");
  const std::vector<uint8_t> bytes = io::encode_jpeg(image.width, image.height, 3, image.rgb);
  if (bytes.empty()) throw IoError("cannot write '" + path + "': the JPEG encoder failed (out of memory?)");
  io::write_atomically(path, [&](std::FILE* f) { return io::write_all(f, bytes.data(), bytes.size()); });
}

}  // namespace mv

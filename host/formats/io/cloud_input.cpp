#include "cloud_input.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "file_ops.h"
#include "megavox/error.h"
#include "point_source.h"

namespace mv::io {

namespace {

// The PLY header's text up to end_header (it is ASCII whatever the body's format), at most 64 KiB.
bool ply_declares_faces(const std::string& path) {
  const std::string head = first_bytes(path, 65536);
  const size_t end = head.find("end_header");
  std::istringstream lines(head.substr(0, end == std::string::npos ? head.size() : end));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string keyword, name;
    uint64_t count = 0;
    if (words >> keyword >> name >> count && keyword == "element" && name == "face" && count > 0) return true;
  }
  return false;
}

}  // namespace

bool is_point_cloud(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // the mesh readers name what is wrong
  const std::string head = first_bytes(path, 4);
  if (head == "LASF") return true;
  if (head != "ply\n" && head != "ply\r") return false;
  return !ply_declares_faces(path);
}

CloudPoints read_cloud(const std::string& path, bool colour) {
  PointReadOptions options;
  options.carry_extra_bytes = false;
  auto source = open_points(path, options);
  const PointCloudInfo& info = source->info();
  CloudPoints out;
  out.format = info.format;
  const bool has_rgb = colour && (info.attributes & kPointRgb);
  std::vector<uint16_t> wide;
  PointColumns batch;
  uint16_t most = 0;
  while (true) {
    batch.clear();
    if (!source->next(batch, 1u << 20)) break;
    const uint64_t n = batch.size();
    for (uint64_t p = 0; p < n; ++p) {
      double w[3];
      for (int a = 0; a < 3; ++a) w[a] = info.offset[a] + info.scale[a] * double(batch.xyz[3 * p + a]);
      out.xyz.insert(out.xyz.end(), w, w + 3);
      out.bounds.extend(w[0], w[1], w[2]);
    }
    if (has_rgb) {
      wide.insert(wide.end(), batch.rgb.begin(), batch.rgb.end());
      for (uint16_t v : batch.rgb) most = std::max(most, v);
    }
  }
  if (out.xyz.empty()) throw Error(path + ": the point cloud has no points");
  if (!has_rgb) return out;
  out.wide_colour = most > 255;
  const int shift = out.wide_colour ? 8 : 0;
  out.rgb.resize(wide.size() / 3);
  for (size_t p = 0; p < out.rgb.size(); ++p)
    out.rgb[p] = uint32_t(wide[3 * p] >> shift) | uint32_t(wide[3 * p + 1] >> shift) << 8 |
                 uint32_t(wide[3 * p + 2] >> shift) << 16;
  return out;
}

}  // namespace mv::io

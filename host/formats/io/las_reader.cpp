// The LAS point reader (las_reader.h): the header through las_header.h, then the point records read in
// buffered batches and split into columns.
#include "las_reader.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "file_ops.h"
#include "las_fields.h"
#include "las_header.h"
#include "laz_records.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

using detail::le;

constexpr uint64_t kBufferBytes = 1 << 20;

class LasSource final : public PointSource {
 public:
  LasSource(const std::string& path, const PointReadOptions& options)
      : path_(path), file_(io::open_regular(path, &size_)) {
    h_ = detail::read_las_header(file_.get(), path, size_);

    info_.format = std::string(h_.compressed ? "LAZ " : "LAS ") + std::to_string(h_.version_major) + "." +
                   std::to_string(h_.version_minor) + ", point format " + std::to_string(h_.point_format);
    info_.points = h_.points;
    info_.attributes = kPointIntensity;
    rgb_offset_ = detail::las_rgb_offset(h_.point_format);
    if (rgb_offset_ != 0) info_.attributes |= kPointRgb;
    if (options.carry_extra_bytes) {
      layout_ = detail::las_record_layout(h_.point_format, h_.record_length - h_.standard_length,
                                          h_.extra_bytes_descriptors);
      info_.attributes |= kPointExtra;
      info_.extra_bytes = layout_.bytes;
      info_.fields = layout_.fields;
    }
    for (int a = 0; a < 3; ++a) {
      info_.scale[a] = h_.scale[a];
      info_.offset[a] = h_.offset[a];
    }
    info_.z_up = true;
    info_.crs = h_.crs;

    const uint64_t buffer = std::min(kBufferBytes, options.ram_bytes);
    batch_ = std::max<uint64_t>(1, buffer / h_.record_length);
    bounds_ = options.bounds;
    if (h_.compressed) {
      laz_ = std::make_unique<LazRecords>(file_.get(), path, size_, h_, options.threads, options.ram_bytes, bounds_);
      info_.points = laz_->points();
      if (laz_->copc()) info_.format += " (COPC)";
      return;
    }
    if (fseeko(file_.get(), static_cast<off_t>(h_.point_offset), SEEK_SET) != 0)
      throw Error(path + ": cannot seek to the point data at byte " + std::to_string(h_.point_offset) + ": " +
                  std::strerror(errno));
  }

  const PointCloudInfo& info() const override { return info_; }

  uint64_t records_read() const override { return read_; }

  uint64_t skip(uint64_t n) override {
    n = std::min(n, info_.points - read_);
    if (laz_) {  // whole chunks unread, then the rest of a chunk decoded and dropped
      const uint64_t passed = laz_->skip_chunks(n);
      read_ += passed;
      for (uint64_t left = n - passed; left > 0;) {
        buffer_.resize(std::min(left, batch_) * h_.record_length);
        const size_t got = laz_->read(buffer_.data(), std::min(left, batch_));
        if (got == 0) truncated();
        read_ += got;
        left -= got;
      }
      return passed;
    }
    read_ += n;
    const uint64_t at = h_.point_offset + read_ * h_.record_length;
    if (fseeko(file_.get(), static_cast<off_t>(at), SEEK_SET) != 0)
      throw Error(path_ + ": cannot seek to point " + std::to_string(read_) + ": " + std::strerror(errno));
    return n;
  }

  bool next(PointColumns& out, size_t max_points) override {
    if (max_points == 0) throw Error(path_ + ": next: max_points must be at least 1");
    if (read_ == info_.points) return false;
    const uint64_t n = std::min<uint64_t>(max_points, info_.points - read_);
    reserve(out, n);
    buffer_.resize(std::min(n, batch_) * h_.record_length);
    for (uint64_t done = 0; done < n;) {
      const uint64_t chunk = std::min(n - done, batch_);
      const size_t got = laz_ ? laz_->read(buffer_.data(), chunk)
                              : io::read_some(file_.get(), buffer_.data(), chunk * h_.record_length, path_) /
                                    h_.record_length;
      decode(out, got);
      read_ += got;
      done += got;
      if (got < chunk) truncated();
    }
    return true;
  }

 private:
  void reserve(PointColumns& out, uint64_t n) const { out.reserve_more(n, info_.attributes, info_.extra_bytes); }

  void decode(PointColumns& out, size_t count) const {
    const bool rgb = info_.attributes & kPointRgb;
    const unsigned char* r = buffer_.data();
    for (size_t i = 0; i < count; ++i, r += h_.record_length) {
      if (bounds_ && !inside(r)) continue;
      out.xyz.insert(out.xyz.end(), {le<int32_t>(r), le<int32_t>(r + 4), le<int32_t>(r + 8)});
      out.intensity.push_back(le<uint16_t>(r + 12));
      if (rgb) {
        const unsigned char* c = r + rgb_offset_;
        out.rgb.insert(out.rgb.end(), {le<uint16_t>(c), le<uint16_t>(c + 2), le<uint16_t>(c + 4)});
      }
      if (info_.extra_bytes) {
        out.extra.resize(out.extra.size() + layout_.bytes);
        detail::las_attributes(h_.point_format, h_.standard_length, layout_, r, out.extra.data() + out.extra.size() - layout_.bytes);
      }
    }
  }

  // The record's world position lies in bounds_ (both ends included).
  bool inside(const unsigned char* r) const {
    for (int a = 0; a < 3; ++a) {
      const double w = h_.offset[a] + h_.scale[a] * static_cast<double>(le<int32_t>(r + 4 * a));
      if (w < (*bounds_)[a] || w > (*bounds_)[3 + a]) return false;
    }
    return true;
  }

  [[noreturn]] void truncated() const {
    throw Error(path_ + ": truncated point data: the header declares " + std::to_string(h_.points) +
                " points, but the file ends after " + std::to_string(read_) + " complete points");
  }

  std::string path_;
  uint64_t size_ = 0;  // before file_: opening it sets the size
  io::FilePtr file_;
  detail::LasHeader h_;
  PointCloudInfo info_;
  uint32_t rgb_offset_ = 0;
  detail::LasRecordLayout layout_;  // the attribute record (with carry_extra_bytes)
  std::optional<std::array<double, 6>> bounds_;
  std::unique_ptr<LazRecords> laz_;  // a LAZ file's records, decompressed
  uint64_t batch_ = 1;               // records per read
  std::vector<unsigned char> buffer_;
  uint64_t read_ = 0;
};

}  // namespace

std::unique_ptr<PointSource> open_las(const std::string& path, const PointReadOptions& options) {
  return std::make_unique<LasSource>(path, options);
}

}  // namespace mv::io

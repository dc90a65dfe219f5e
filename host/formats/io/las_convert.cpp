// LAS and LAZ to plain LAS (las_convert.h).
#include "las_convert.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <utility>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include "atomic_file.h"
#include "file_ops.h"
#include "io/header_numbers.h"
#include "las_header.h"
#include "laz_records.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

using detail::num;

constexpr uint64_t kVlrHeader = 54, kEvlrHeader = 60;
constexpr uint64_t kBatchBytes = 64ull << 20;

const char* compressor_name(laz::Compressor c) {
  switch (c) {
    case laz::Compressor::pointwise: return "pointwise";
    case laz::Compressor::pointwise_chunked: return "pointwise chunked";
    case laz::Compressor::layered_chunked: return "layered chunked";
    default: return "none";
  }
}


bool is_copc_record(const uint8_t* user_id) { return std::memcmp(user_id, "copc", 5) == 0; }

template <class T>
void put_le(uint8_t* p, T v) {
  for (size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<uint8_t>(static_cast<uint64_t>(v) >> (8 * i));
}

// The points of an open LAS or LAZ file, batch by batch.
class Records {
 public:
  Records(const std::string& path, unsigned threads, const std::optional<std::array<double, 6>>& bounds = {})
      : path_(path), file_(open_regular(path, &size_)) {
    h_ = detail::read_las_header(file_.get(), path, size_);
    report_.input_format = std::string(h_.compressed ? "LAZ " : "LAS ") + num(h_.version_major) + "." +
                           num(h_.version_minor) + ", point format " + num(h_.point_format);
    report_.points = h_.points;
    report_.record_length = h_.record_length;
    if (h_.compressed) {
      laz_ = std::make_unique<LazRecords>(file_.get(), path, size_, h_, threads, kBatchBytes, bounds);
      const laz::Schema& s = laz_->schema();
      report_.input_format += std::string(laz_->copc() ? " COPC" : "") + " (LASzip " + num(s.version_major) + "." +
                              num(s.version_minor) + ", " + compressor_name(s.compressor) + ", " +
                              num(laz_->chunks_in_file()) + " chunk" + (laz_->chunks_in_file() == 1 ? ")" : "s)");
      total_ = laz_->points();
      report_.chunks = laz_->chunks_in_file();
      report_.chunks_read = laz_->chunks();
    }
    batch_ = std::max<uint64_t>(1, kBatchBytes / h_.record_length);
    if (!laz_) total_ = h_.points;
    report_.points = total_;
  }

  // The next batch of records into `out`; false after the last.
  bool next(std::vector<uint8_t>& out) {
    if (done_ == total_) return false;
    const uint64_t n = std::min(batch_, total_ - done_);
    out.resize(n * h_.record_length);
    size_t got;
    if (laz_) {
      got = laz_->read(out.data(), n);
    } else {
      if (done_ == 0 && fseeko(file_.get(), static_cast<off_t>(h_.point_offset), SEEK_SET) != 0)
        throw Error(path_ + ": cannot seek to the point data: " + std::strerror(errno));
      got = read_some(file_.get(), out.data(), out.size(), path_) / h_.record_length;
    }
    if (got != n)
      throw Error(path_ + ": truncated point data: the header declares " + num(total_) + " points, but only " +
                  num(done_ + got) + " could be read");
    done_ += n;
    return true;
  }

  const detail::LasHeader& header() const { return h_; }
  std::FILE* file() const { return file_.get(); }
  uint64_t size() const { return size_; }
  uint64_t done() const { return done_; }
  LasConvertReport& report() { return report_; }

 private:
  std::string path_;
  uint64_t size_ = 0;
  FilePtr file_;
  detail::LasHeader h_;
  std::unique_ptr<LazRecords> laz_;
  uint64_t batch_ = 1, done_ = 0, total_ = 0;
  LasConvertReport report_;
};

// The header and VLRs of the plain copy: LASzip's record dropped, the offsets and the format byte rewritten.
std::vector<uint8_t> plain_head(Records& in, const std::string& path) {
  const detail::LasHeader& h = in.header();
  std::vector<uint8_t> head = read_at(in.file(), 0, h.point_offset, path);
  std::vector<uint8_t> out(head.begin(), head.begin() + h.header_size);
  uint64_t at = h.header_size;
  uint32_t kept = 0;
  for (uint32_t k = 0; k < h.vlr_count; ++k) {
    const uint64_t length = head[at + 20] | (head[at + 21] << 8);  // bounded by read_las_header
    // LASzip's record describes the compression and COPC's the chunks' octree: neither holds for the copy.
    const bool laszip = std::memcmp(&head[at + 2], "laszip encoded", 15) == 0;
    if (!laszip && !is_copc_record(&head[at + 2])) {
      out.insert(out.end(), head.begin() + at, head.begin() + at + kVlrHeader + length);
      ++kept;
    }
    at += kVlrHeader + length;
  }
  out.insert(out.end(), head.begin() + at, head.end());  // bytes a writer left between the records and the points
  out[104] = h.point_format;
  put_le<uint32_t>(&out[96], static_cast<uint32_t>(out.size()));
  put_le<uint32_t>(&out[100], kept);
  return out;
}

// LAS 1.4's extended records but COPC's hierarchy, and their count.
std::pair<std::vector<uint8_t>, uint32_t> plain_evlrs(Records& in, const std::string& path) {
  const detail::LasHeader& h = in.header();
  std::vector<uint8_t> out;
  uint32_t kept = 0;
  uint64_t at = h.evlr_start;
  for (uint32_t k = 0; k < h.evlr_count; ++k) {  // bounded by read_las_header
    const std::vector<uint8_t> head = read_at(in.file(), at, kEvlrHeader, path);
    uint64_t length = 0;
    for (int i = 7; i >= 0; --i) length = (length << 8) | head[20 + i];
    if (!is_copc_record(&head[2])) {
      const std::vector<uint8_t> body = read_at(in.file(), at + kEvlrHeader, length, path);
      out.insert(out.end(), head.begin(), head.end());
      out.insert(out.end(), body.begin(), body.end());
      ++kept;
    }
    at += kEvlrHeader + length;
  }
  return {std::move(out), kept};
}

// What the header says of the points a bounded copy keeps: their count, their count by return number, and
// their bounds.
struct KeptPoints {
  uint64_t count = 0;
  uint64_t by_return[15] = {};
  int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
};

// Keeps the records of `batch` whose world position lies in `box`, in order, and counts them into `kept`.
void keep_inside(std::vector<uint8_t>& batch, const detail::LasHeader& h, const std::array<double, 6>& box,
                 KeptPoints& kept) {
  const size_t length = h.record_length;
  size_t to = 0;
  for (size_t from = 0; from < batch.size(); from += length) {
    const uint8_t* r = batch.data() + from;
    int32_t xyz[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      std::memcpy(&xyz[a], r + 4 * a, 4);
      const double w = h.offset[a] + h.scale[a] * xyz[a];
      inside = inside && w >= box[a] && w <= box[3 + a];
    }
    if (!inside) continue;
    ++kept.count;
    const unsigned ret = h.point_format >= 6 ? r[14] & 15 : r[14] & 7;
    if (ret >= 1) ++kept.by_return[ret - 1];
    for (int a = 0; a < 3; ++a) kept.lo[a] = std::min(kept.lo[a], xyz[a]), kept.hi[a] = std::max(kept.hi[a], xyz[a]);
    if (to != from) std::memmove(batch.data() + to, r, length);
    to += length;
  }
  batch.resize(to);
}

// The header fields a bounded copy changes: point counts (legacy and 64-bit), counts by return, bounds.
void patch_counts(std::vector<uint8_t>& head, const detail::LasHeader& h, const KeptPoints& kept) {
  const bool legacy = h.point_format < 6 && kept.count <= UINT32_MAX;
  put_le<uint32_t>(&head[107], legacy ? static_cast<uint32_t>(kept.count) : 0);
  for (int r = 0; r < 5; ++r)
    put_le<uint32_t>(&head[111 + 4 * r], legacy && kept.by_return[r] <= UINT32_MAX ? static_cast<uint32_t>(kept.by_return[r]) : 0);
  for (int a = 0; a < 3; ++a) {
    const double lo = kept.count ? h.offset[a] + h.scale[a] * kept.lo[a] : 0;
    const double hi = kept.count ? h.offset[a] + h.scale[a] * kept.hi[a] : 0;
    std::memcpy(&head[179 + 16 * a], &hi, 8);
    std::memcpy(&head[187 + 16 * a], &lo, 8);
  }
  if (h.version_minor >= 4) {
    put_le<uint64_t>(&head[247], kept.count);
    for (int r = 0; r < 15; ++r) put_le<uint64_t>(&head[255 + 8 * r], kept.by_return[r]);
  }
}

}  // namespace

LasConvertReport write_plain_las(const std::string& input, const std::string& output, unsigned threads,
                                 const std::function<void(uint64_t)>& progress,
                                 const std::optional<std::array<double, 6>>& bounds) {
  Records in(input, threads, bounds);
  const detail::LasHeader& h = in.header();
  std::vector<uint8_t> head = plain_head(in, input);
  const auto [evlrs, evlr_count] = plain_evlrs(in, input);
  LasConvertReport& report = in.report();
  std::vector<uint8_t> batch;
  KeptPoints kept;
  double decoding = 0;
  write_atomically(output, [&](std::FILE* f) {
    if (!write_all(f, head.data(), head.size())) return false;
    for (;;) {
      const auto start = std::chrono::steady_clock::now();
      const bool more = in.next(batch);
      if (more && bounds) keep_inside(batch, h, *bounds, kept);
      decoding += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!more) break;
      if (!bounds) kept.count += batch.size() / h.record_length;
      if (!write_all(f, batch.data(), batch.size())) return false;
      if (progress) progress(in.done());
    }
    if (!write_all(f, evlrs.data(), evlrs.size())) return false;
    // The fields only known now: the extended records' start (and the counts and bounds of a bounded copy).
    if (bounds) patch_counts(head, h, kept);
    if (h.version_minor >= 4) {
      put_le<uint64_t>(&head[235], evlr_count ? head.size() + kept.count * h.record_length : 0);
      put_le<uint32_t>(&head[243], evlr_count);
    }
    return fseeko(f, 0, SEEK_SET) == 0 && write_all(f, head.data(), h.header_size) && fseeko(f, 0, SEEK_END) == 0;
  });
  report.decode_seconds = decoding;
  report.points_written = kept.count;
  report.bytes_written = head.size() + kept.count * h.record_length + evlrs.size();
  return report;
}

LasConvertReport decode_las_points(const std::string& input, unsigned threads) {
  const auto start = std::chrono::steady_clock::now();
  Records in(input, threads);
  std::vector<uint8_t> batch;
  while (in.next(batch)) {
  }
  in.report().decode_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return in.report();
}

}  // namespace mv::io

// The LAS header reader (las_header.h): the fixed header block of each version, the (extended) variable-length
// records walked within their bounds, and the CRS picked out of them.
#include "las_header.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "file_ops.h"
#include "io/header_numbers.h"
#include "megavox/error.h"

namespace mv::io::detail {

namespace {

// Point data record formats 0-10 (LAS 1.4, table "Point Data Record Format" sizes); 4, 5, 9 and 10 are 1, 3,
// 6 and 8 with a 29-byte waveform packet descriptor after them.
constexpr uint32_t kStandardLength[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr uint32_t kRgbOffset[] = {0, 0, 20, 28, 0, 28, 0, 30, 30, 0, 30};

constexpr uint32_t kLegacyHeader = 227;  // LAS 1.0-1.2
constexpr uint32_t kHeader13 = 235;      // + start of waveform data
constexpr uint32_t kHeader14 = 375;      // + EVLRs and the 64-bit counts
constexpr uint64_t kVlrHeader = 54, kEvlrHeader = 60;
constexpr uint64_t kMaxCrsBytes = 1 << 20;  // real WKT is a few KiB
constexpr uint16_t kWktRecord = 2112, kGeoKeyRecord = 34735, kLaszipRecord = 22204, kExtraBytesRecord = 4;
constexpr uint64_t kMaxDescriptorBytes = 192 * 1024;  // a record has at most 65535 extra bytes
constexpr uint16_t kProjectedCsKey = 3072, kGeographicKey = 2048, kUserDefined = 32767;

// "GeoTIFF keys (EPSG:2992)": the projected (else geographic) CRS code of a GeoKeyDirectory, whose entries
// are (key id, tag location, count, value) with the value inline when the location is 0.
std::string geokey_summary(const std::vector<unsigned char>& bytes) {
  const size_t words = bytes.size() / 2;
  auto word = [&](size_t i) { return le<uint16_t>(bytes.data() + 2 * i); };
  uint16_t projected = 0, geographic = 0;
  if (words >= 4) {
    const size_t keys = word(3);
    for (size_t k = 0; k < keys && 4 * k + 7 < words; ++k) {
      const size_t at = 4 + 4 * k;
      if (word(at + 1) != 0) continue;
      if (word(at) == kProjectedCsKey) projected = word(at + 3);
      if (word(at) == kGeographicKey) geographic = word(at + 3);
    }
  }
  const uint16_t code = projected ? projected : geographic;
  if (code == 0) return "GeoTIFF keys";
  if (code == kUserDefined) return "GeoTIFF keys (user-defined CRS)";
  return "GeoTIFF keys (EPSG:" + num(code) + ")";
}

class HeaderReader {
 public:
  HeaderReader(std::FILE* file, const std::string& path, uint64_t size) : file_(file), path_(path), size_(size) {}

  LasHeader read() {
    read_fixed();
    read_vlrs();
    check_points();
    read_evlrs();
    if (h_.compressed && h_.laszip.empty())
      fail("the point format says LAZ (compressed), but the file has no LASzip record (\"laszip encoded\" 22204)");
    h_.crs = !wkt_.empty() ? wkt_ : geokeys_;
    return h_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  std::vector<unsigned char> bytes_at(uint64_t at, uint64_t n) const { return io::read_at(file_, at, n, path_); }

  std::string version() const { return "LAS " + num(h_.version_major) + "." + num(h_.version_minor); }

  void read_fixed() {
    const std::vector<unsigned char> b = bytes_at(0, std::min<uint64_t>(size_, kHeader14));
    if (b.size() < 4 || std::memcmp(b.data(), "LASF", 4) != 0) fail("not a LAS file (it does not start with 'LASF')");
    if (b.size() < kLegacyHeader)
      fail("truncated LAS header: the file has " + num(size_) + " bytes, a LAS header needs at least " +
           num(kLegacyHeader));
    h_.version_major = b[24];
    h_.version_minor = b[25];
    if (h_.version_major != 1 || h_.version_minor > 4) fail(version() + " is not supported (LAS 1.0 to 1.4 are read)");
    const uint32_t minimum = h_.version_minor >= 4 ? kHeader14 : h_.version_minor == 3 ? kHeader13 : kLegacyHeader;
    if (b.size() < minimum)
      fail("truncated LAS header: the file has " + num(size_) + " bytes, a " + version() + " header needs " +
           num(minimum));
    h_.header_size = le<uint16_t>(&b[94]);
    h_.point_offset = le<uint32_t>(&b[96]);
    h_.vlr_count = le<uint32_t>(&b[100]);
    h_.record_length = le<uint16_t>(&b[105]);
    h_.legacy_points = le<uint32_t>(&b[107]);
    for (int a = 0; a < 3; ++a) {
      h_.scale[a] = le<double>(&b[131 + 8 * a]);
      h_.offset[a] = le<double>(&b[155 + 8 * a]);
      h_.max[a] = le<double>(&b[179 + 16 * a]);
      h_.min[a] = le<double>(&b[187 + 16 * a]);
    }
    if (h_.version_minor >= 3) h_.waveform_start = le<uint64_t>(&b[227]);
    if (h_.version_minor >= 4) {
      h_.evlr_start = le<uint64_t>(&b[235]);
      h_.evlr_count = le<uint32_t>(&b[243]);
      h_.points64 = le<uint64_t>(&b[247]);
    }

    if (h_.header_size < minimum)
      fail("bad LAS header: its size field says " + num(h_.header_size) + " bytes, a " + version() +
           " header has at least " + num(minimum));
    if (h_.header_size > size_)
      fail("truncated LAS header: the header has " + num(h_.header_size) + " bytes, the file " + num(size_));
    // LASzip marks a compressed file by setting bit 7 (bit 6 in early versions) of the point format.
    h_.compressed = (b[104] & 0xC0) != 0;
    const uint8_t format = b[104] & 0x3F;
    h_.point_format = format;
    h_.standard_length = las_standard_record_length(format);
    if (h_.standard_length == 0)
      fail("point data record format " + num(format) + " is not supported; formats 0 to 10 are read");
    if (h_.record_length < h_.standard_length)
      fail("bad LAS header: point records of " + num(h_.record_length) + " bytes are shorter than the " +
           num(h_.standard_length) + " bytes of point format " + num(format));
    static constexpr char kAxis[] = "XYZ";
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(h_.scale[a]) || h_.scale[a] == 0)
        fail("bad LAS header: the " + std::string(1, kAxis[a]) + " scale factor " + std::to_string(h_.scale[a]) +
             " is not a finite non-zero number");
      if (!std::isfinite(h_.offset[a]))
        fail("bad LAS header: the " + std::string(1, kAxis[a]) + " offset is not finite");
    }
    // LAS 1.4 counts in 64 bits; the legacy 32-bit count is 0 where it cannot apply, else the same.
    h_.points = h_.legacy_points;
    if (h_.version_minor >= 4 && h_.points64 != 0) {
      if (h_.legacy_points != 0 && h_.legacy_points != h_.points64)
        fail("bad LAS header: the legacy point count " + num(h_.legacy_points) + " disagrees with the 64-bit count " +
             num(h_.points64));
      h_.points = h_.points64;
    }
    if (h_.point_offset < h_.header_size)
      fail("bad LAS header: the point data starts at byte " + num(h_.point_offset) + ", inside the " +
           num(h_.header_size) + "-byte header");
    if (h_.point_offset > size_)
      fail("truncated LAS file: the point data should start at byte " + num(h_.point_offset) + ", but the file has " +
           num(size_) + " bytes");
  }

  // The VLRs fill the bytes between the header and the point data.
  void read_vlrs() {
    const uint64_t room = h_.point_offset - h_.header_size;
    if (sat_mul(h_.vlr_count, kVlrHeader) > room)
      fail("bad LAS header: " + num(h_.vlr_count) + " variable-length records cannot fit in the " + num(room) +
           " bytes between the header and the point data");
    uint64_t at = h_.header_size;
    for (uint32_t k = 0; k < h_.vlr_count; ++k) {
      const std::vector<unsigned char> v = bytes_at(at, kVlrHeader);
      const uint64_t length = le<uint16_t>(&v[20]);
      if (at + kVlrHeader + length > h_.point_offset)
        fail("variable-length record " + num(k) + " (at byte " + num(at) + ", " + num(kVlrHeader + length) +
             " bytes) runs past the start of the point data at byte " + num(h_.point_offset));
      consider(v.data() + 2, le<uint16_t>(&v[18]), at + kVlrHeader, length);
      at += kVlrHeader + length;
    }
  }

  // Refused before anything is allocated: a truncated file or a garbage count. A LAZ file's count is checked
  // against its chunk table instead.
  void check_points() const {
    if (h_.compressed) return;
    const uint64_t available = size_ - h_.point_offset;
    if (sat_mul(h_.points, h_.record_length) > available)
      fail("truncated point data: the header declares " + num(h_.points) + " points of " + num(h_.record_length) +
           " bytes from byte " + num(h_.point_offset) + ", but the file ends after " +
           num(available / h_.record_length) + " complete points");
  }

  // LAS 1.4's extended records follow the point data.
  void read_evlrs() {
    if (h_.evlr_count == 0) return;
    const uint64_t points_end =  // bounded by check_points
        h_.compressed ? h_.point_offset : h_.point_offset + h_.points * h_.record_length;
    if (h_.evlr_start < points_end || h_.evlr_start > size_)
      fail("bad LAS header: the extended variable-length records start at byte " + num(h_.evlr_start) +
           ", not between the end of the point data (byte " + num(points_end) + ") and the end of the file (byte " +
           num(size_) + ")");
    if (sat_mul(h_.evlr_count, kEvlrHeader) > size_ - h_.evlr_start)
      fail("bad LAS header: " + num(h_.evlr_count) + " extended variable-length records cannot fit in the " +
           num(size_ - h_.evlr_start) + " bytes after byte " + num(h_.evlr_start));
    uint64_t at = h_.evlr_start;
    for (uint32_t k = 0; k < h_.evlr_count; ++k) {
      if (size_ - at < kEvlrHeader)
        fail("extended variable-length record " + num(k) + " at byte " + num(at) + " runs past the end of the file");
      const std::vector<unsigned char> v = bytes_at(at, kEvlrHeader);
      const uint64_t length = le<uint64_t>(&v[20]);
      if (length > size_ - at - kEvlrHeader)
        fail("extended variable-length record " + num(k) + " (at byte " + num(at) + ", " + num(length) +
             " bytes after its header) runs past the end of the file (" + num(size_) + " bytes)");
      consider(v.data() + 2, le<uint16_t>(&v[18]), at + kEvlrHeader, length);
      at += kEvlrHeader + length;
    }
  }

  // Keeps the first WKT and the first GeoKeyDirectory of the projection records.
  void consider(const unsigned char* user_id, uint16_t record_id, uint64_t at, uint64_t length) {
    const std::string_view user(reinterpret_cast<const char*>(user_id),
                                strnlen(reinterpret_cast<const char*>(user_id), 16));
    if (user == "laszip encoded" && record_id == kLaszipRecord && h_.laszip.empty()) {
      const std::vector<unsigned char> bytes = bytes_at(at, std::min<uint64_t>(length, 1 << 16));
      h_.laszip.assign(bytes.begin(), bytes.end());
      if (h_.laszip.empty()) fail("the LASzip record is empty");
      return;
    }
    if (user == "copc" && record_id == 1 && h_.copc.empty() && length == 160) {
      const std::vector<unsigned char> bytes = bytes_at(at, length);
      h_.copc.assign(bytes.begin(), bytes.end());
      return;
    }
    if (user == "LASF_Spec" && record_id == kExtraBytesRecord) {
      if (h_.extra_bytes_descriptors.size() + length > kMaxDescriptorBytes)
        fail("the Extra Bytes records describe more than " + num(kMaxDescriptorBytes / 192) + " fields");
      const std::vector<unsigned char> bytes = bytes_at(at, length - length % 192);
      h_.extra_bytes_descriptors.insert(h_.extra_bytes_descriptors.end(), bytes.begin(), bytes.end());
      return;
    }
    if (user != "LASF_Projection") return;
    if (record_id == kWktRecord && wkt_.empty()) {
      if (length > kMaxCrsBytes)
        fail("the OGC WKT record at byte " + num(at) + " has " + num(length) + " bytes, more than the " +
             num(kMaxCrsBytes) + " a CRS is read with");
      const std::vector<unsigned char> text = bytes_at(at, length);
      wkt_.assign(text.begin(), std::find(text.begin(), text.end(), '\0'));  // stored NUL-terminated
      while (!wkt_.empty() && std::isspace(static_cast<unsigned char>(wkt_.back()))) wkt_.pop_back();
    } else if (record_id == kGeoKeyRecord && geokeys_.empty()) {
      geokeys_ = geokey_summary(bytes_at(at, std::min(length, kMaxCrsBytes)));
    }
  }

  std::FILE* file_;
  const std::string& path_;
  uint64_t size_;
  LasHeader h_;
  std::string wkt_, geokeys_;
};

}  // namespace

uint32_t las_standard_record_length(unsigned format) { return format < 11 ? kStandardLength[format] : 0; }

uint32_t las_rgb_offset(unsigned format) { return format < 11 ? kRgbOffset[format] : 0; }

LasHeader read_las_header(std::FILE* file, const std::string& path, uint64_t file_size) {
  return HeaderReader(file, path, file_size).read();
}


}  // namespace mv::io::detail

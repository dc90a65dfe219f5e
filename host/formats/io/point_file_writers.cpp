// PLY and LAS from a point source (point_file_writers.h).
#include "point_file_writers.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "file_ops.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

constexpr size_t kBatch = 1 << 16;

template <class T>
void append_le(std::vector<uint8_t>& out, T v) {
  uint8_t b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);  // little-endian, as megavox's hosts are
  out.insert(out.end(), b, b + sizeof b);
}

const char* ply_type(PointFieldType t) {
  switch (t) {
    case PointFieldType::u8: return "uchar";
    case PointFieldType::i8: return "char";
    case PointFieldType::u16: return "ushort";
    case PointFieldType::i16: return "short";
    case PointFieldType::u32: return "uint";
    case PointFieldType::i32: return "int";
    case PointFieldType::f32: return "float";
    default: return "double";  // f64, and 64-bit integers, which PLY has no type for
  }
}

// One value of field `f` (element k) from a point's record into `out`, as ply_type writes it.
void append_field(std::vector<uint8_t>& out, const PointField& f, const uint8_t* record, uint32_t k) {
  const uint8_t* p = record + f.offset + k * point_field_size(f.type);
  if (f.type == PointFieldType::u64 || f.type == PointFieldType::i64) {
    uint64_t u;
    std::memcpy(&u, p, 8);
    append_le<double>(out, f.type == PointFieldType::u64 ? static_cast<double>(u)
                                                         : static_cast<double>(static_cast<int64_t>(u)));
    return;
  }
  out.insert(out.end(), p, p + point_field_size(f.type));
}

bool write_bytes(std::FILE* f, const std::vector<uint8_t>& b) { return write_all(f, b.data(), b.size()); }

// A field of the LAS attribute record by name, or null.
const PointField* named(const PointCloudInfo& info, const char* name) {
  for (const PointField& f : info.fields)
    if (f.name == name) return &f;
  return nullptr;
}

template <class T>
T field_value(const PointField* f, const uint8_t* record, T otherwise) {
  if (!f) return otherwise;
  T v;
  std::memcpy(&v, record + f->offset, sizeof v);
  return v;
}

constexpr const char* kLasFields[] = {"return_number",       "number_of_returns",  "classification",
                                      "classification_flags", "scanner_channel",    "scan_direction_flag",
                                      "edge_of_flight_line", "user_data",          "scan_angle",
                                      "point_source_id",      "gps_time"};

bool is_las_field(const std::string& name) {
  return std::any_of(std::begin(kLasFields), std::end(kLasFields), [&](const char* n) { return name == n; });
}

// The Extra Bytes record's entry for a run of `f`: LAS data types 1-10 are the ten field types in order.
std::vector<uint8_t> extra_bytes_descriptor(const std::string& name, int data_type, uint8_t options,
                                            const std::string& description) {
  std::vector<uint8_t> d(192, 0);
  d[2] = static_cast<uint8_t>(data_type);
  d[3] = options;
  std::memcpy(&d[4], name.data(), std::min<size_t>(name.size(), 31));
  std::memcpy(&d[160], description.data(), std::min<size_t>(description.size(), 31));
  return d;
}

}  // namespace

uint64_t write_ply_points(PointSource& source, const std::string& output,
                          const std::function<void(uint64_t)>& progress) {
  const PointCloudInfo& info = source.info();
  const bool normal = info.attributes & kPointNormal, rgb = info.attributes & kPointRgb;
  const bool intensity = info.attributes & kPointIntensity;
  const std::vector<PointField> fields = info.attributes & kPointExtra ? info.fields : std::vector<PointField>{};
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment megavox points convert from " + info.format + "\n";
  if (!info.crs.empty()) {
    std::string crs = info.crs;
    std::replace(crs.begin(), crs.end(), '\n', ' ');
    header += "comment crs " + crs + "\n";
  }
  header += "element vertex " + std::to_string(info.points) + "\n";
  header += "property double x\nproperty double y\nproperty double z\n";
  if (normal) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (rgb) header += "property ushort red\nproperty ushort green\nproperty ushort blue\n";
  if (intensity) header += "property ushort intensity\n";
  for (const PointField& f : fields)
    for (uint32_t k = 0; k < f.count; ++k)
      header += std::string("property ") + ply_type(f.type) + " " + f.name + (f.count > 1 ? "_" + std::to_string(k) : "") + "\n";
  header += "end_header\n";

  uint64_t written = 0;
  write_atomically(output, [&](std::FILE* file) {
    if (!write_all(file, header.data(), header.size())) return false;
    PointColumns c;
    std::vector<uint8_t> out;
    for (;;) {
      c.clear();
      if (!source.next(c, kBatch)) break;
      out.clear();
      for (uint64_t i = 0; i < c.size(); ++i) {
        for (int a = 0; a < 3; ++a) append_le<double>(out, info.offset[a] + info.scale[a] * c.xyz[3 * i + a]);
        if (normal)
          for (int a = 0; a < 3; ++a) append_le<float>(out, c.normal[3 * i + a]);
        if (rgb)
          for (int a = 0; a < 3; ++a) append_le<uint16_t>(out, c.rgb[3 * i + a]);
        if (intensity) append_le<uint16_t>(out, c.intensity[i]);
        const uint8_t* record = fields.empty() ? nullptr : &c.extra[info.extra_bytes * i];
        for (const PointField& f : fields)
          for (uint32_t k = 0; k < f.count; ++k) append_field(out, f, record, k);
      }
      if (!write_bytes(file, out)) return false;
      written += c.size();
      if (progress) progress(written);
    }
    return true;
  });
  if (written != info.points)
    throw Error(output + ": the source delivered " + std::to_string(written) + " points where its header declared " +
                std::to_string(info.points));
  return written;
}

uint64_t write_las_points(PointSource& source, const std::string& output,
                          const std::function<void(uint64_t)>& progress) {
  const PointCloudInfo& info = source.info();
  const bool rgb = info.attributes & kPointRgb, normal = info.attributes & kPointNormal;
  const bool record_fields = info.attributes & kPointExtra;
  // Fields that are not LAS's own travel as extra bytes, as do normals.
  std::vector<PointField> extras;
  if (record_fields)
    for (const PointField& f : info.fields)
      if (!is_las_field(f.name) && f.name != "nir") extras.push_back(f);
  std::vector<uint8_t> descriptors;
  uint32_t extra_length = 0;
  for (const PointField& f : extras) {
    const bool typed = f.count == 1 || f.count == 2 || f.count == 3;
    const int type = typed ? 1 + static_cast<int>(f.type) + 10 * static_cast<int>(f.count - 1) : 0;
    const uint32_t bytes = point_field_size(f.type) * f.count;
    const uint8_t options = typed ? static_cast<uint8_t>((f.scale != 1 ? 8 : 0) | (f.add != 0 ? 16 : 0))
                                  : static_cast<uint8_t>(std::min<uint32_t>(bytes, 255));
    std::vector<uint8_t> d = extra_bytes_descriptor(f.name, type, options, f.description);
    std::memcpy(&d[112], &f.scale, 8);
    std::memcpy(&d[136], &f.add, 8);
    descriptors.insert(descriptors.end(), d.begin(), d.end());
    extra_length += bytes;
  }
  if (normal) {
    for (const char* n : {"nx", "ny", "nz"}) {
      const std::vector<uint8_t> d = extra_bytes_descriptor(n, 9, 0, "normal");  // 9: float
      descriptors.insert(descriptors.end(), d.begin(), d.end());
    }
    extra_length += 12;
  }
  const uint8_t format = rgb ? 7 : 6;
  const uint32_t standard = rgb ? 36 : 30, length = standard + extra_length;
  if (length > 65535) throw Error(output + ": records of " + std::to_string(length) + " bytes do not fit LAS");

  std::vector<uint8_t> head(375, 0);
  std::memcpy(&head[0], "LASF", 4);
  head[24] = 1;
  head[25] = 4;
  const std::string software = "megavox points convert";
  std::memcpy(&head[58], software.data(), software.size());
  auto put16 = [&](size_t at, uint16_t v) { std::memcpy(&head[at], &v, 2); };
  auto put32 = [&](size_t at, uint32_t v) { std::memcpy(&head[at], &v, 4); };
  auto put64 = [&](size_t at, uint64_t v) { std::memcpy(&head[at], &v, 8); };
  auto putd = [&](size_t at, double v) { std::memcpy(&head[at], &v, 8); };
  put16(94, 375);
  std::vector<uint8_t> vlrs;
  if (!descriptors.empty()) {
    std::vector<uint8_t> v(54, 0);
    std::memcpy(&v[2], "LASF_Spec", 9);
    const uint16_t id = 4, bytes = static_cast<uint16_t>(descriptors.size());
    std::memcpy(&v[18], &id, 2);
    std::memcpy(&v[20], &bytes, 2);
    vlrs.insert(vlrs.end(), v.begin(), v.end());
    vlrs.insert(vlrs.end(), descriptors.begin(), descriptors.end());
  }
  uint32_t vlr_count = descriptors.empty() ? 0 : 1;
  // The source's CRS where it is WKT (a LAS file's GeoTIFF keys are only summarised, so they cannot travel).
  if (!info.crs.empty() && info.crs.rfind("GeoTIFF keys", 0) != 0 && info.crs.size() < 65000) {
    std::vector<uint8_t> v(54, 0);
    std::memcpy(&v[2], "LASF_Projection", 15);
    const uint16_t id = 2112, bytes = static_cast<uint16_t>(info.crs.size() + 1);
    std::memcpy(&v[18], &id, 2);
    std::memcpy(&v[20], &bytes, 2);
    vlrs.insert(vlrs.end(), v.begin(), v.end());
    vlrs.insert(vlrs.end(), info.crs.begin(), info.crs.end());
    vlrs.push_back(0);
    put16(6, 16);  // global encoding: the CRS is WKT
    ++vlr_count;
  }
  put32(96, static_cast<uint32_t>(375 + vlrs.size()));
  put32(100, vlr_count);
  head[104] = format;
  put16(105, static_cast<uint16_t>(length));
  for (int a = 0; a < 3; ++a) {
    putd(131 + 8 * a, info.scale[a]);
    putd(155 + 8 * a, info.offset[a]);
  }

  const PointField* fld[std::size(kLasFields)] = {};
  if (record_fields)
    for (size_t k = 0; k < std::size(kLasFields); ++k) fld[k] = named(info, kLasFields[k]);
  uint64_t written = 0, by_return[15] = {};
  int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
  write_atomically(output, [&](std::FILE* file) {
    if (!write_bytes(file, head) || !write_bytes(file, vlrs)) return false;
    PointColumns c;
    std::vector<uint8_t> out;
    for (;;) {
      c.clear();
      if (!source.next(c, kBatch)) break;
      out.assign(c.size() * length, 0);
      for (uint64_t i = 0; i < c.size(); ++i) {
        uint8_t* r = &out[i * length];
        const uint8_t* rec = record_fields ? &c.extra[info.extra_bytes * i] : nullptr;
        std::memcpy(r, &c.xyz[3 * i], 12);
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c.xyz[3 * i + a]), hi[a] = std::max(hi[a], c.xyz[3 * i + a]);
        if (info.attributes & kPointIntensity) std::memcpy(r + 12, &c.intensity[i], 2);
        const uint8_t ret = rec ? field_value<uint8_t>(fld[0], rec, 1) : 1, num = rec ? field_value<uint8_t>(fld[1], rec, 1) : 1;
        r[14] = static_cast<uint8_t>((ret & 15) | (num & 15) << 4);
        if (ret >= 1 && ret <= 15) ++by_return[ret - 1];
        if (rec) {
          r[15] = static_cast<uint8_t>((field_value<uint8_t>(fld[3], rec, 0) & 15) | (field_value<uint8_t>(fld[4], rec, 0) & 3) << 4 |
                                       (field_value<uint8_t>(fld[5], rec, 0) & 1) << 6 | (field_value<uint8_t>(fld[6], rec, 0) & 1) << 7);
          r[16] = field_value<uint8_t>(fld[2], rec, 0);
          r[17] = field_value<uint8_t>(fld[7], rec, 0);
          const float degrees = field_value<float>(fld[8], rec, 0.0f);
          const int16_t angle = static_cast<int16_t>(std::clamp(std::lround(degrees / 0.006), -30000L, 30000L));
          std::memcpy(r + 18, &angle, 2);
          const uint16_t source_id = field_value<uint16_t>(fld[9], rec, 0);
          std::memcpy(r + 20, &source_id, 2);
          const double gps = field_value<double>(fld[10], rec, 0.0);
          std::memcpy(r + 22, &gps, 8);
        }
        if (rgb) std::memcpy(r + 30, &c.rgb[3 * i], 6);
        uint32_t at = standard;
        for (const PointField& f : extras) {
          const uint32_t bytes = point_field_size(f.type) * f.count;
          std::memcpy(r + at, rec + f.offset, bytes);
          at += bytes;
        }
        if (normal) std::memcpy(r + at, &c.normal[3 * i], 12);
      }
      if (!write_bytes(file, out)) return false;
      written += c.size();
      if (progress) progress(written);
    }
    // What is known only now: the count, the counts by return and the bounds.
    put64(247, written);
    for (int k = 0; k < 15; ++k) put64(255 + 8 * k, by_return[k]);
    for (int a = 0; a < 3; ++a) {
      putd(179 + 16 * a, written ? info.offset[a] + info.scale[a] * hi[a] : 0);
      putd(187 + 16 * a, written ? info.offset[a] + info.scale[a] * lo[a] : 0);
    }
    return fseeko(file, 0, SEEK_SET) == 0 && write_bytes(file, head) && fseeko(file, 0, SEEK_END) == 0;
  });
  return written;
}

}  // namespace mv::io

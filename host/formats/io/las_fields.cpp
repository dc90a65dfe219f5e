// The LAS attribute record (las_fields.h).
#include "las_fields.h"

#include "las_header.h"

#include <cmath>
#include <cstring>
#include <set>
#include <string>

namespace mv::io::detail {

namespace {

constexpr uint32_t kDescriptorBytes = 192;

bool las_has_gps(unsigned format) { return format == 1 || format >= 3; }

// Formats 4, 5, 9 and 10: the byte where their waveform packet descriptor starts, else 0.
uint32_t las_wave_packet_at(unsigned format) {
  switch (format) {
    case 4: return 28;
    case 5: return 34;
    case 9: return 30;
    case 10: return 38;
    default: return 0;
  }
}

void add_field(LasRecordLayout& l, const char* name, PointFieldType type, const char* description) {
  PointField f;
  f.name = name;
  f.type = type;
  f.offset = l.bytes;
  f.description = description;
  l.bytes += point_field_size(type);
  l.fields.push_back(std::move(f));
}

// An Extra Bytes descriptor's value type: 1-10 one value, 11-30 (deprecated) two or three; 0 undocumented.
bool descriptor_type(uint8_t data_type, PointFieldType& type, uint32_t& count) {
  if (data_type < 1 || data_type > 30) return false;
  type = static_cast<PointFieldType>((data_type - 1) % 10);
  count = 1 + (data_type - 1) / 10;
  return true;
}

std::string fixed_text(const uint8_t* p, size_t n) {
  std::string s(reinterpret_cast<const char*>(p), strnlen(reinterpret_cast<const char*>(p), n));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '_';
  return s;
}

}  // namespace

LasRecordLayout las_record_layout(unsigned format, uint32_t surplus, const std::vector<uint8_t>& descriptors) {
  LasRecordLayout l;
  using T = PointFieldType;
  add_field(l, "return_number", T::u8, "the pulse's return this point is (1 = first)");
  add_field(l, "number_of_returns", T::u8, "returns of the pulse");
  add_field(l, "classification", T::u8, "ASPRS class (2 ground, 6 building, ...)");
  add_field(l, "classification_flags", T::u8, "bit 0 synthetic, 1 key-point, 2 withheld, 3 overlap");
  add_field(l, "scanner_channel", T::u8, "the scanner head (LAS 1.4)");
  add_field(l, "scan_direction_flag", T::u8, "1: the mirror moved positive");
  add_field(l, "edge_of_flight_line", T::u8, "1: the last point of a scan line");
  add_field(l, "user_data", T::u8, "free for the producer's use");
  add_field(l, "scan_angle", T::f32, "degrees off nadir");
  add_field(l, "point_source_id", T::u16, "the flight line or source");
  if (las_has_gps(format)) add_field(l, "gps_time", T::f64, "GPS time of the pulse");
  if (format == 8 || format == 10) add_field(l, "nir", T::u16, "near infrared");
  if (las_wave_packet_at(format)) {  // the descriptor of the point's waveform (the waveform itself is not read)
    add_field(l, "wave_packet_descriptor_index", T::u8, "the Waveform Packet Descriptor record (0: none)");
    add_field(l, "wave_packet_offset", T::u64, "bytes from the waveform data's start to this point's packet");
    add_field(l, "wave_packet_bytes", T::u32, "the waveform packet's size");
    add_field(l, "return_point_waveform_location", T::f32, "picoseconds from the packet's first sample");
    add_field(l, "x_t", T::f32, "the pulse's direction: x per picosecond");
    add_field(l, "y_t", T::f32, "the pulse's direction: y per picosecond");
    add_field(l, "z_t", T::f32, "the pulse's direction: z per picosecond");
  }
  l.standard = l.bytes;

  // The extra bytes: each documented run named and typed, the rest one unnamed run.
  std::set<std::string> names;
  for (const PointField& f : l.fields) names.insert(f.name);
  uint32_t at = 0;
  for (size_t d = 0; d + kDescriptorBytes <= descriptors.size() && at < surplus; d += kDescriptorBytes) {
    const uint8_t* e = descriptors.data() + d;
    PointField f;
    uint32_t bytes;
    if (e[2] == 0) {  // undocumented: `options` bytes
      f.type = T::u8;
      f.count = e[3];
      bytes = e[3];
    } else if (descriptor_type(e[2], f.type, f.count)) {
      bytes = point_field_size(f.type) * f.count;
    } else {
      break;  // a type LAS does not define: what follows cannot be placed
    }
    if (bytes == 0 || bytes > surplus - at) break;
    f.name = fixed_text(e + 4, 32);
    if (f.name.empty()) f.name = "extra_" + std::to_string(at);
    for (int k = 2; !names.insert(f.name).second; ++k) f.name = fixed_text(e + 4, 32) + "_" + std::to_string(k);
    f.description = fixed_text(e + 160, 32);
    double scale, add;
    std::memcpy(&scale, e + 112, 8);
    std::memcpy(&add, e + 136, 8);
    if ((e[3] & 8) && std::isfinite(scale) && scale != 0) f.scale = scale;
    if ((e[3] & 16) && std::isfinite(add)) f.add = add;
    f.offset = l.bytes + at;
    at += bytes;
    l.fields.push_back(std::move(f));
  }
  if (at < surplus) {
    PointField f;
    f.name = names.count("extra_bytes") ? "extra_bytes_" + std::to_string(at) : "extra_bytes";
    f.type = T::u8;
    f.count = surplus - at;
    f.offset = l.bytes + at;
    f.description = "extra bytes no Extra Bytes record describes";
    l.fields.push_back(std::move(f));
  }
  l.bytes += surplus;
  return l;
}

void las_attributes(unsigned format, uint32_t standard_length, const LasRecordLayout& layout,
                    const unsigned char* r, uint8_t* out) {
  float scan_angle;
  const uint16_t source = le<uint16_t>(format >= 6 ? r + 20 : r + 18);
  if (format >= 6) {
    out[0] = r[14] & 15;
    out[1] = r[14] >> 4;
    out[2] = r[16];
    out[3] = r[15] & 15;
    out[4] = (r[15] >> 4) & 3;
    out[5] = (r[15] >> 6) & 1;
    out[6] = r[15] >> 7;
    scan_angle = static_cast<float>(le<int16_t>(r + 18) * 0.006);
  } else {
    out[0] = r[14] & 7;
    out[1] = (r[14] >> 3) & 7;
    out[2] = r[15] & 31;
    out[3] = r[15] >> 5;
    out[4] = 0;
    out[5] = (r[14] >> 6) & 1;
    out[6] = r[14] >> 7;
    scan_angle = static_cast<float>(static_cast<int8_t>(r[16]));
  }
  out[7] = r[17];
  // The record is little-endian, as the hosts megavox runs on are.
  std::memcpy(out + 8, &scan_angle, 4);
  std::memcpy(out + 12, &source, 2);
  uint32_t at = 14;
  if (las_has_gps(format)) {
    std::memcpy(out + at, format >= 6 ? r + 22 : r + 20, 8);
    at += 8;
  }
  if (format == 8 || format == 10) {
    std::memcpy(out + at, r + 36, 2);
    at += 2;
  }
  if (const uint32_t wave = las_wave_packet_at(format)) {  // 29 bytes, little-endian as the record
    std::memcpy(out + at, r + wave, 29);
    at += 29;
  }
  std::memcpy(out + at, r + standard_length, layout.bytes - layout.standard);
}

}  // namespace mv::io::detail

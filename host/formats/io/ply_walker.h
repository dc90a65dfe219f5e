// The PLY element walker: PlyMeshReader's state and the format-independent templates that read the vertices,
// skip other elements and stream the faces, one value at a time through a value reader (ply_values.h) or,
// on binary fast paths, whole records from the buffer. Internal to host/io: included by ply_reader.cpp,
// which holds the layout checks and instantiates the walkers for each format.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ply_header.h"
#include "ply_reader.h"
#include "ply_source.h"
#include "ply_values.h"
#include "temp_file.h"

namespace mv::io {

using detail::AsciiValues;
using detail::BinaryValues;
using detail::decode;
using detail::Element;
using detail::EndOfData;
using detail::Format;
using detail::Header;
using detail::is_integer;
using detail::num;
using detail::Property;
using detail::Scalar;
using detail::scalar_name;
using detail::scalar_size;
using detail::Source;

struct PlyMeshReader::Impl {
  static constexpr size_t kNone = static_cast<size_t>(-1);

  Source src;
  Header header;
  PlyInfo info;
  uint64_t ram_bytes;
  std::vector<float> positions;        // in RAM, or
  std::unique_ptr<TempFile> scratch;   // mapped from a scratch file past ram_bytes
  float* mapped = nullptr;
  std::span<float> pos;                // whichever holds them

  size_t vertex_el = kNone;
  size_t face_el = kNone;
  std::vector<int> vertex_role;  // per vertex property: 0/1/2 for x/y/z, 3/4/5 for red/green/blue, -1 skipped
  bool colour_roles = false;     // red, green and blue are read (uchar or ushort)
  bool colour_wide = false;      // any of them ushort
  std::vector<uint16_t> rgb16;   // 3 per vertex as stored, while reading
  std::vector<uint32_t> colours; // per vertex 0xBBGGRR (8-bit: ushort keeps its high byte unless all fit 8 bits)
  size_t index_prop = kNone;     // the face element's index list
  double vertex_limit = 0;       // indices must be below this

  // Streaming state: the next element to read, and the face (and polygon) being read.
  size_t next_el = 0;
  uint64_t face = 0;
  uint64_t poly_left = 0;  // indices of the current polygon still to read
  uint32_t poly_first = 0;
  uint32_t poly_prev = 0;
  bool done = false;
  // A share of the faces (select_faces): faces before face_end, each a triangle, then the end.
  uint64_t face_end = UINT64_MAX;
  bool triangles_only = false;
  uint64_t face_start = 0, spanned = 0;  // the face element's first byte; the bytes a share spans
  uint64_t share_bytes = 0;               // the bytes of a share's faces
  // Vertices left unread at opening (a build over ranks reads them in shares, read_vertex_range): where the
  // first one starts, and the bytes of them read since.
  bool vertices_deferred = false;
  uint64_t vertex_offset = 0, vertex_bytes_read = 0;

  // Defined in ply_reader.cpp: construction, the layout checks, the messages of faults.
  Impl(const std::string& path, uint64_t ram, bool defer_vertices);
  ~Impl();
  [[noreturn]] void fail(const std::string& what) const;
  [[noreturn]] void fail_at(uint64_t line, const std::string& what) const;
  static size_t find_property(const Element& e, std::string_view name);
  // The vertex and face elements and the properties read of them; fail()s on a layout the reader refuses.
  void find_layout();
  // Refuses counts the file cannot hold, before anything is allocated: a truncated file or a garbage count.
  void check_counts() const;
  [[noreturn]] void truncated(const Element& e, uint64_t complete) const;
  // Bytes per entry of an element of scalars, 0 if it has lists or records too large for the fast paths.
  static size_t record_bytes(const Element& e);

  // Runs f with the value reader of this file's format over `from` (src by default): the element walkers below
  // are format-independent.
  template <class F>
  void with_values(F&& f) { with_values_on(src, f); }
  template <class F>
  void with_values_on(Source& from, F&& f) {
    constexpr bool host_le = std::endian::native == std::endian::little;
    if (header.format == Format::ascii) {
      AsciiValues v(from);
      f(v);
    } else if ((header.format == Format::binary_le) == host_le) {
      BinaryValues<false> v(from);
      f(v);
    } else {
      BinaryValues<true> v(from);
      f(v);
    }
  }

  // Checks on values read from the data, shared by the generic walkers and the binary fast paths. The
  // messages are built out of line so that the loops stay small.
  template <class V>
  [[noreturn, gnu::cold, gnu::noinline]] void fail_entry(const V& v, const Element& e, uint64_t i, const std::string& what) const {
    fail(v.where() + e.name + " " + num(i) + what);
  }

  template <class V>
  [[gnu::always_inline]] uint64_t checked_length(const V& v, const Element& e, uint64_t i, const Property& p, double n) const {
    if (n < 0) [[unlikely]]
      fail_entry(v, e, i, ": list '" + p.name + "' has negative length " + std::to_string(static_cast<int64_t>(n)));
    return static_cast<uint64_t>(n);
  }

  template <class V>
  [[gnu::always_inline]] float checked_coordinate(const V& v, const Element& e, uint64_t i, const Property& p, double d) const {
    // Checked before the conversion: a double beyond the float range does not convert.
    if (!(std::fabs(d) <= std::numeric_limits<float>::max())) [[unlikely]]
      fail_entry(v, e, i, ": coordinate " + p.name + " = " + std::to_string(d) + " is not a finite float");
    return static_cast<float>(d);
  }

  template <class V>
  [[gnu::always_inline]] uint32_t checked_index(const V& v, const Element& e, double d) const {
    if (!(d >= 0 && d < vertex_limit)) [[unlikely]]
      fail_entry(v, e, face, " refers to vertex " + std::to_string(static_cast<int64_t>(d)) + " (only " +
                                 num(info.vertices) + " vertices)");
    return static_cast<uint32_t>(d);
  }

  template <class V>
  [[gnu::always_inline]] uint64_t checked_face_size(const V& v, const Element& e, uint64_t n) const {
    if (n < 3) [[unlikely]]
      fail_entry(v, e, face, " has " + num(n) + " vertex indices (a face needs at least 3)");
    if (triangles_only && n != 3) [[unlikely]]
      fail_entry(v, e, face, " has " + num(n) + " vertex indices: a share of the faces read by offset needs triangles");
    return n;
  }

  template <class V>
  uint64_t list_length(V& v, const Element& e, uint64_t i, const Property& p) {
    return checked_length(v, e, i, p, v.scalar(p.count_type));
  }

  template <class V>
  void skip_property(V& v, const Element& e, uint64_t i, const Property& p) {
    v.skip(p.type, p.is_list ? list_length(v, e, i, p) : 1);
  }

  template <class V>
  void skip_element(V& v, const Element& e) {
    if (e.props.empty()) return;  // no data, however large the count
    uint64_t i = 0;
    try {
      for (; i < e.count; ++i)
        for (const Property& p : e.props) skip_property(v, e, i, p);
    } catch (const EndOfData&) {
      truncated(e, i);
    }
  }

  template <class V>
  void read_vertices(V& v) {
    const Element& e = header.elements[vertex_el];
    const uint64_t bytes = 12 * e.count;  // bounded by the file size (check_counts)
    if (bytes > ram_bytes) {
      scratch = std::make_unique<TempFile>(src.path() + ": vertex positions over the memory budget");
      mapped = scratch->map_floats(bytes);
      pos = {mapped, 3 * e.count};
    } else {
      positions.resize(3 * e.count);
      pos = positions;
    }
    if (colour_roles) rgb16.resize(3 * e.count);
    if constexpr (V::kBinary) {
      if (size_t record = record_bytes(e)) {
        read_vertex_records(v, src, e, record, 0, e.count, pos.data(), rgb16.data());
        return finish_colours();
      }
    }
    float* out = pos.data();
    uint64_t i = 0;
    try {
      for (; i < e.count; ++i, out += 3) {
        for (size_t k = 0; k < e.props.size(); ++k) {
          const Property& p = e.props[k];
          const int role = vertex_role[k];
          if (role < 0) skip_property(v, e, i, p);
          else if (role < 3) out[role] = checked_coordinate(v, e, i, p, v.scalar(p.type));
          else rgb16[3 * i + (role - 3)] = checked_channel(v, e, i, p, v.scalar(p.type));
        }
      }
    } catch (const EndOfData&) {
      truncated(e, i);
    }
    finish_colours();
  }

  template <class V>
  [[gnu::always_inline]] uint16_t checked_channel(const V& v, const Element& e, uint64_t i, const Property& p, double d) const {
    if (!(d >= 0 && d <= (p.type == Scalar::u8 ? 255.0 : 65535.0))) [[unlikely]]
      fail_entry(v, e, i, ": colour " + p.name + " = " + std::to_string(d) + " is out of range");
    return static_cast<uint16_t>(d);
  }

  // The 8-bit colours from the stored ones: ushort values keep their high byte unless every value fits 8 bits.
  void finish_colours() {
    if (!colour_roles) return;
    bool narrow = true;
    for (uint16_t c : rgb16) narrow = narrow && c < 256;
    const int shift = colour_wide && !narrow ? 8 : 0;
    colours.resize(rgb16.size() / 3);
    for (size_t i = 0; i < colours.size(); ++i)
      colours[i] = uint32_t(rgb16[3 * i] >> shift) | uint32_t(rgb16[3 * i + 1] >> shift) << 8 |
                   uint32_t(rgb16[3 * i + 2] >> shift) << 16;
    rgb16 = {};
  }

  // Binary fast path: fixed-size vertex records [first, first + count) decoded straight from `from`'s buffer,
  // many at a time, into `out` (3 floats each) and, with colours, `rgb` (3 channels each).
  template <class V>
  void read_vertex_records(const V& v, Source& from, const Element& e, size_t record, uint64_t first, uint64_t count,
                           float* out, uint16_t* rgb) {
    size_t offset[6] = {};
    const Property* prop[6] = {};
    for (size_t k = 0, at = 0; k < e.props.size(); at += scalar_size(e.props[k].type), ++k) {
      if (vertex_role[k] < 0) continue;
      offset[vertex_role[k]] = at;
      prop[vertex_role[k]] = &e.props[k];
    }
    const uint64_t last = first + count;
    for (uint64_t i = first; i < last;) {
      auto [begin, end] = from.window(record);
      uint64_t n = std::min<uint64_t>(last - i, static_cast<uint64_t>(end - begin) / record);
      if (n == 0) truncated(e, i);
      for (const char* r = begin; r != begin + n * record; r += record, out += 3, ++i) {
        for (int a = 0; a < 3; ++a) out[a] = checked_coordinate(v, e, i, *prop[a], decode<V::kSwap>(r + offset[a], prop[a]->type));
        if (colour_roles) {
          for (int a = 0; a < 3; ++a)
            rgb[a] = checked_channel(v, e, i, *prop[3 + a], decode<V::kSwap>(r + offset[3 + a], prop[3 + a]->type));
          rgb += 3;
        }
      }
      from.advance(n * record);
    }
  }

  // Reads elements up to the face element (left for next_triangles) or to the end of the file.
  template <class V>
  void advance(V& v) {
    for (; next_el < header.elements.size(); ++next_el) {
      if (next_el == face_el) return;
      if (next_el == vertex_el) read_vertices(v);
      else skip_element(v, header.elements[next_el]);
    }
    done = true;
  }

  // Emits one triangle per call, reading whatever the face element's layout puts before it; a polygon's
  // state survives between calls, so a batch may end inside a polygon.
  template <class V>
  void stream_faces(V& v, std::vector<uint32_t>& out, size_t max_triangles) {
    const Element& e = header.elements[face_el];
    const Property& ip = e.props[index_prop];
    const bool only_indices = e.props.size() == 1;
    out.reserve(3 * std::min<uint64_t>({max_triangles, e.count - face + 1, uint64_t{1} << 20}));
    try {
      while (out.size() / 3 < max_triangles) {
        if constexpr (V::kBinary) {
          if (only_indices && poly_left == 0 && read_face_records(v, e, ip, out, max_triangles)) continue;
        }
        if (poly_left == 0) {
          if (face == face_end) {  // the end of a share: what follows is another's
            done = true;
            return;
          }
          if (face == e.count) {
            ++next_el;
            advance(v);
            return;
          }
          for (size_t k = 0; k < index_prop; ++k) skip_property(v, e, face, e.props[k]);
          poly_left = checked_face_size(v, e, list_length(v, e, face, ip)) - 2;
          poly_first = checked_index(v, e, v.scalar(ip.type));
          poly_prev = checked_index(v, e, v.scalar(ip.type));
        }
        uint32_t cur = checked_index(v, e, v.scalar(ip.type));
        out.insert(out.end(), {poly_first, poly_prev, cur});
        poly_prev = cur;
        if (--poly_left == 0) {
          for (size_t k = index_prop + 1; k < e.props.size(); ++k) skip_property(v, e, face, e.props[k]);
          ++face;
        }
      }
    } catch (const EndOfData&) {
      truncated(e, face);
    }
  }

  // Binary fast path for faces that are just an index list: whole polygons decoded straight from the buffer
  // while they fit in it and in the batch. False if not even one did (the generic step takes over).
  template <class V>
  bool read_face_records(const V& v, const Element& e, const Property& ip, std::vector<uint32_t>& out,
                         size_t max_triangles) {
    const size_t count_bytes = scalar_size(ip.count_type), index_bytes = scalar_size(ip.type);
    auto [p, end] = src.window(count_bytes + 3 * index_bytes);
    const char* begin = p;
    while (face < std::min(e.count, face_end) && static_cast<size_t>(end - p) >= count_bytes) {
      uint64_t n = checked_length(v, e, face, ip, decode<V::kSwap>(p, ip.count_type));
      if (static_cast<uint64_t>(end - p - count_bytes) / index_bytes < n) break;  // continues past the buffer
      if (max_triangles - out.size() / 3 < checked_face_size(v, e, n) - 2) break;  // continues past the batch
      const char* q = p + count_bytes;
      uint32_t first = checked_index(v, e, decode<V::kSwap>(q, ip.type));
      uint32_t prev = checked_index(v, e, decode<V::kSwap>(q + index_bytes, ip.type));
      for (uint64_t k = 2; k < n; ++k) {
        uint32_t cur = checked_index(v, e, decode<V::kSwap>(q + k * index_bytes, ip.type));
        out.push_back(first);
        out.push_back(prev);
        out.push_back(cur);
        prev = cur;
      }
      p = q + n * index_bytes;
      ++face;
    }
    src.advance(static_cast<size_t>(p - begin));
    return p != begin;
  }
};

}  // namespace mv::io

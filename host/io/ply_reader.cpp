#include "ply_reader.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string_view>
#include <utility>

#include "megavox/error.h"
#include "ply_header.h"
#include "temp_file.h"

namespace mv::io {

using detail::Element;
using detail::EndOfData;
using detail::Format;
using detail::Header;
using detail::HeaderLines;
using detail::is_integer;
using detail::num;
using detail::Property;
using detail::Scalar;
using detail::scalar_name;
using detail::scalar_size;

namespace {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);

constexpr size_t kMaxToken = 64;  // longest ascii value ("-1.2345678901234567e-308" is 24)
constexpr size_t kBufferBytes = 1 << 20;

uint64_t sat_mul(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

uint64_t sat_add(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_add_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

// ---------------------------------------------------------------------------------------------------
// Buffered input

// Reads the file in large blocks and hands out small contiguous pieces of it.
class Source final : public HeaderLines {
 public:
  explicit Source(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "rb"), &std::fclose) {
    if (!file_) throw Error("cannot open '" + path + "': " + std::strerror(errno));
    std::error_code ec;
    // The size bounds every count in the header; a pipe or directory has none.
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": not a regular file");
    size_ = std::filesystem::file_size(path, ec);
    if (ec) throw Error(path + ": cannot read its size: " + ec.message());
    std::setvbuf(file_.get(), nullptr, _IONBF, 0);  // reads are large already; stdio's buffer would add a copy
    capacity_ = std::clamp<uint64_t>(size_, 4096, kBufferBytes);
    buffer_ = std::make_unique_for_overwrite<char[]>(capacity_);
    pos_ = end_ = buffer_.get();
  }
  const std::string& path() const override { return path_; }
  uint64_t size() const { return size_; }
  uint64_t consumed() const override { return read_ - static_cast<uint64_t>(end_ - pos_); }
  uint64_t line() const override { return line_; }  // ascii: the line being read, 1-based

  // The next n bytes, contiguous (n <= 8: one binary value).
  const char* take(size_t n) {
    if (static_cast<size_t>(end_ - pos_) < n && !fill(n)) throw EndOfData{};
    const char* p = pos_;
    pos_ += n;
    return p;
  }

  // The buffered bytes from the read position, after trying to make at least n available (fewer at the end
  // of the file). For decoding many binary records at once; advance() moves past what was used.
  std::pair<const char*, const char*> window(size_t n) {
    if (static_cast<size_t>(end_ - pos_) < n) fill(n);
    return {pos_, end_};
  }
  void advance(size_t n) { pos_ += n; }

  void skip(uint64_t n) {
    while (n > 0) {
      if (pos_ == end_ && !fill(1)) throw EndOfData{};
      size_t k = static_cast<size_t>(std::min<uint64_t>(n, static_cast<uint64_t>(end_ - pos_)));
      pos_ += k;
      n -= k;
    }
  }

  // One header line without "\n" or "\r\n". False if it is longer than max_chars.
  bool header_line(std::string& out, size_t max_chars) override {
    out.clear();
    for (;;) {
      if (pos_ == end_ && !fill(1)) throw EndOfData{};
      char c = *pos_++;
      if (c == '\n') break;
      if (out.size() == max_chars) return false;
      out.push_back(c);
    }
    ++line_;
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return true;
  }

  // The next whitespace-separated ascii token; valid until the next call.
  std::string_view token() {
    for (;; ++pos_) {
      if (pos_ == end_ && !fill(1)) throw EndOfData{};
      if (*pos_ == '\n') ++line_;
      else if (!is_space(*pos_)) break;
    }
    size_t n = 1;
    while ((pos_ + n < end_ || fill(n + 1)) && !is_space(pos_[n]) && pos_[n] != '\n')
      if (++n > kMaxToken) throw Error(path_ + ": line " + num(line_) + ": value longer than " + num(kMaxToken) + " characters");
    std::string_view t(pos_, n);
    pos_ += n;
    return t;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

  // Makes at least n bytes available after pos_ (moving the rest to the front); false if the file ends first.
  bool fill(size_t n) {
    size_t have = static_cast<size_t>(end_ - pos_);
    std::memmove(buffer_.get(), pos_, have);
    pos_ = buffer_.get();
    end_ = pos_ + have;
    while (have < n) {
      size_t got = std::fread(end_, 1, capacity_ - have, file_.get());
      if (got == 0) {
        if (std::ferror(file_.get())) throw Error(path_ + ": read error: " + std::strerror(errno));
        return false;
      }
      end_ += got;
      have += got;
      read_ += got;
    }
    return true;
  }

  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  uint64_t size_ = 0;
  size_t capacity_ = 0;
  std::unique_ptr<char[]> buffer_;
  char* pos_ = nullptr;
  char* end_ = nullptr;
  uint64_t read_ = 0;
  uint64_t line_ = 1;
};

// ---------------------------------------------------------------------------------------------------
// Values: reading one scalar, all the generic element walkers need to know of the format. (The binary fast
// paths in the reader decode whole records from the buffer instead.)

template <class T, bool Swap>
T load(const char* p) {
  using U = std::conditional_t<sizeof(T) == 1, uint8_t,
            std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  U u;
  std::memcpy(&u, p, sizeof u);
  if constexpr (Swap && sizeof(T) == 2) u = __builtin_bswap16(u);
  if constexpr (Swap && sizeof(T) == 4) u = __builtin_bswap32(u);
  if constexpr (Swap && sizeof(T) == 8) u = __builtin_bswap64(u);
  return std::bit_cast<T>(u);
}

// One binary value in file byte order; Swap when that differs from the host's. double holds every type exactly.
// Always inlined: the binary fast paths call it per value, and the switch then folds into their loops.
template <bool Swap>
[[gnu::always_inline]] inline double decode(const char* p, Scalar t) {
  switch (t) {
    case Scalar::i8: return load<int8_t, Swap>(p);
    case Scalar::u8: return load<uint8_t, Swap>(p);
    case Scalar::i16: return load<int16_t, Swap>(p);
    case Scalar::u16: return load<uint16_t, Swap>(p);
    case Scalar::i32: return load<int32_t, Swap>(p);
    case Scalar::u32: return load<uint32_t, Swap>(p);
    case Scalar::f32: return load<float, Swap>(p);
    case Scalar::f64: return load<double, Swap>(p);
  }
  return 0;
}

template <bool Swap>
class BinaryValues {
 public:
  static constexpr bool kSwap = Swap;
  static constexpr bool kBinary = true;
  explicit BinaryValues(Source& src) : src_(src) {}

  double scalar(Scalar t) { return decode<Swap>(src_.take(scalar_size(t)), t); }
  void skip(Scalar t, uint64_t n) { src_.skip(sat_mul(n, scalar_size(t))); }
  std::string where() const { return {}; }

 private:
  Source& src_;
};

class AsciiValues {
 public:
  static constexpr bool kBinary = false;
  explicit AsciiValues(Source& src) : src_(src) {}

  double scalar(Scalar t) {
    std::string_view s = src_.token();
    return is_integer(t) ? parse_integer(s, t) : parse_real(s, t);
  }
  // Skipped values are still checked: the format is strict.
  void skip(Scalar t, uint64_t n) {
    for (uint64_t i = 0; i < n; ++i) scalar(t);
  }
  std::string where() const { return "line " + num(src_.line()) + ": "; }

 private:
  double parse_integer(std::string_view s, Scalar t) {
    static constexpr int64_t lo[] = {INT8_MIN, 0, INT16_MIN, 0, INT32_MIN, 0};
    static constexpr int64_t hi[] = {INT8_MAX, UINT8_MAX, INT16_MAX, UINT16_MAX, INT32_MAX, UINT32_MAX};
    std::string_view digits = s.size() > 1 && s[0] == '+' ? s.substr(1) : s;
    int64_t v = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    size_t i = static_cast<size_t>(t);
    if (ec != std::errc{} || end != digits.data() + digits.size() || v < lo[i] || v > hi[i]) bad(s, t);
    return static_cast<double>(v);
  }
  double parse_real(std::string_view s, Scalar t) {
    std::string_view digits = s.size() > 1 && s[0] == '+' ? s.substr(1) : s;
    double v = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    // Out-of-range values become +-inf so that the caller reports them as non-finite.
    if (ec == std::errc::result_out_of_range) v = digits[0] == '-' ? -HUGE_VAL : HUGE_VAL;
    else if (ec != std::errc{}) bad(s, t);
    if (end != digits.data() + digits.size()) bad(s, t);
    return v;
  }
  [[noreturn]] void bad(std::string_view s, Scalar t) const {
    throw Error(src_.path() + ": " + where() + "'" + std::string(s) + "' is not a valid " + std::string(scalar_name(t)));
  }

  Source& src_;
};

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Reader

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
  std::vector<int> vertex_role;  // per vertex property: 0/1/2 for x/y/z, -1 skipped
  size_t index_prop = kNone;     // the face element's index list
  double vertex_limit = 0;       // indices must be below this

  // Streaming state: the next element to read, and the face (and polygon) being read.
  size_t next_el = 0;
  uint64_t face = 0;
  uint64_t poly_left = 0;  // indices of the current polygon still to read
  uint32_t poly_first = 0;
  uint32_t poly_prev = 0;
  bool done = false;

  Impl(const std::string& path, uint64_t ram) : src(path), header(detail::parse_header(src)), ram_bytes(ram) {
    check_counts();
    find_layout();
    info = {header.elements[vertex_el].count, face_el == kNone ? 0 : header.elements[face_el].count,
            detail::format_name(header.format), header.comments};
    vertex_limit = static_cast<double>(info.vertices);
    with_values([&](auto& v) { advance(v); });
  }

  ~Impl() { TempFile::unmap(mapped, pos.size_bytes()); }

  [[noreturn]] void fail(const std::string& what) const { throw Error(src.path() + ": " + what); }
  [[noreturn]] void fail_at(uint64_t line, const std::string& what) const { fail("line " + num(line) + ": " + what); }

  // Runs f with the value reader of this file's format: the element walkers below are format-independent.
  template <class F>
  void with_values(F&& f) {
    constexpr bool host_le = std::endian::native == std::endian::little;
    if (header.format == Format::ascii) {
      AsciiValues v(src);
      f(v);
    } else if ((header.format == Format::binary_le) == host_le) {
      BinaryValues<false> v(src);
      f(v);
    } else {
      BinaryValues<true> v(src);
      f(v);
    }
  }

  static size_t find_property(const Element& e, std::string_view name) {
    for (size_t i = 0; i < e.props.size(); ++i)
      if (e.props[i].name == name) return i;
    return kNone;
  }

  void find_layout() {
    const auto& els = header.elements;
    for (size_t i = 0; i < els.size(); ++i) {
      if (els[i].name == "vertex") vertex_el = i;
      if (els[i].name == "face") face_el = i;
    }
    if (vertex_el == kNone) fail("no 'vertex' element");
    const Element& ve = els[vertex_el];
    if (ve.count > (uint64_t{1} << 32)) fail_at(ve.line, num(ve.count) + " vertices exceed the 32-bit index range");
    vertex_role.assign(ve.props.size(), -1);
    for (int axis = 0; axis < 3; ++axis) {
      const char name[2] = {static_cast<char>('x' + axis), 0};
      size_t p = find_property(ve, name);
      if (p == kNone) fail_at(ve.line, "element 'vertex' has no property '" + std::string(name) + "'");
      if (ve.props[p].is_list) fail_at(ve.props[p].line, "vertex property '" + std::string(name) + "' is a list");
      vertex_role[p] = axis;
    }
    if (face_el == kNone) return;
    const Element& fe = els[face_el];
    if (face_el < vertex_el) fail_at(fe.line, "element 'face' comes before 'vertex' (faces must follow the vertices)");
    index_prop = find_property(fe, "vertex_indices");
    if (index_prop == kNone) index_prop = find_property(fe, "vertex_index");
    if (index_prop == kNone || !fe.props[index_prop].is_list)
      fail_at(fe.line, "element 'face' has no list property 'vertex_indices' or 'vertex_index'");
    const Property& ip = fe.props[index_prop];
    if (!is_integer(ip.type))
      fail_at(ip.line, "list '" + ip.name + "' must hold integer indices, not " + std::string(scalar_name(ip.type)));
  }

  // Refuses counts the file cannot hold, before anything is allocated: a truncated file or a garbage count.
  // Each entry needs at least its scalars and list counts (binary) or 2 characters per value, "0 " (ascii).
  void check_counts() const {
    bool ascii = header.format == Format::ascii;
    uint64_t data_bytes = src.size() - src.consumed();
    uint64_t available = data_bytes + (ascii ? 1 : 0);  // ascii: the last value may lack its "\n"
    uint64_t need = 0;
    for (const Element& e : header.elements) {
      uint64_t per_entry = 0;
      for (const Property& p : e.props) per_entry += ascii ? 2 : scalar_size(p.is_list ? p.count_type : p.type);
      uint64_t total = sat_add(need, sat_mul(per_entry, e.count));
      if (total > available)
        fail("truncated: expected " + num(e.count) + " " + plural(e) + ", but the " + num(data_bytes) +
             " bytes after the header hold at most " + num((available - need) / per_entry));
      need = total;
    }
  }

  static std::string plural(const Element& e) {
    return e.name == "vertex" ? "vertices" : e.name == "face" ? "faces" : "'" + e.name + "' elements";
  }

  [[noreturn]] void truncated(const Element& e, uint64_t complete) const {
    fail("truncated: expected " + num(e.count) + " " + plural(e) + ", file ends after " + num(complete));
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

  // Bytes per entry of an element of scalars, 0 if it has lists or records too large for the fast paths.
  static size_t record_bytes(const Element& e) {
    size_t bytes = 0;
    for (const Property& p : e.props) {
      if (p.is_list) return 0;
      bytes += scalar_size(p.type);
    }
    return bytes <= 4096 ? bytes : 0;  // the source buffer holds at least 4096 bytes
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
    if constexpr (V::kBinary) {
      if (size_t record = record_bytes(e)) return read_vertex_records(v, e, record);
    }
    float* out = pos.data();
    uint64_t i = 0;
    try {
      for (; i < e.count; ++i, out += 3) {
        for (size_t k = 0; k < e.props.size(); ++k) {
          const Property& p = e.props[k];
          if (vertex_role[k] < 0) skip_property(v, e, i, p);
          else out[vertex_role[k]] = checked_coordinate(v, e, i, p, v.scalar(p.type));
        }
      }
    } catch (const EndOfData&) {
      truncated(e, i);
    }
  }

  // Binary fast path: fixed-size vertex records decoded straight from the buffer, many at a time.
  template <class V>
  void read_vertex_records(const V& v, const Element& e, size_t record) {
    size_t offset[3] = {};
    const Property* prop[3] = {};
    for (size_t k = 0, at = 0; k < e.props.size(); at += scalar_size(e.props[k].type), ++k) {
      if (vertex_role[k] < 0) continue;
      offset[vertex_role[k]] = at;
      prop[vertex_role[k]] = &e.props[k];
    }
    float* out = pos.data();
    for (uint64_t i = 0; i < e.count;) {
      auto [begin, end] = src.window(record);
      uint64_t n = std::min<uint64_t>(e.count - i, static_cast<uint64_t>(end - begin) / record);
      if (n == 0) truncated(e, i);
      for (const char* r = begin; r != begin + n * record; r += record, out += 3, ++i)
        for (int a = 0; a < 3; ++a) out[a] = checked_coordinate(v, e, i, *prop[a], decode<V::kSwap>(r + offset[a], prop[a]->type));
      src.advance(n * record);
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
    while (face < e.count && static_cast<size_t>(end - p) >= count_bytes) {
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

PlyMeshReader::PlyMeshReader(const std::string& path, uint64_t ram_bytes)
    : impl_(std::make_unique<Impl>(path, ram_bytes)) {}
PlyMeshReader::~PlyMeshReader() = default;
PlyMeshReader::PlyMeshReader(PlyMeshReader&&) noexcept = default;
PlyMeshReader& PlyMeshReader::operator=(PlyMeshReader&&) noexcept = default;

const PlyInfo& PlyMeshReader::info() const { return impl_->info; }

std::span<const float> PlyMeshReader::positions() const { return impl_->pos; }
bool PlyMeshReader::positions_mapped() const { return impl_->mapped != nullptr; }

bool PlyMeshReader::next_triangles(std::vector<uint32_t>& indices, size_t max_triangles) {
  indices.clear();
  if (max_triangles == 0) impl_->fail("next_triangles: max_triangles must be at least 1");
  if (impl_->done) return false;
  impl_->with_values([&](auto& v) { impl_->stream_faces(v, indices, max_triangles); });
  return !indices.empty();
}

}  // namespace mv::io

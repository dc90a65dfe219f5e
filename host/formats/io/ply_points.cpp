// The PLY point reader (ply_points.h): the vertex layout it reads, the grid of the first pass and the batches
// of the second, over the PLY reader's header parser (ply_header.h) and value readers (ply_values.h).
#include "ply_points.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "megavox/error.h"
#include "ply_header.h"
#include "ply_source.h"
#include "ply_values.h"

namespace mv::io {

namespace {

using detail::decode;
using detail::Element;
using detail::EndOfData;
using detail::Format;
using detail::Header;
using detail::is_integer;
using detail::num;
using detail::Property;
using detail::Scalar;
using detail::scalar_size;
using detail::Source;

// What a vertex property is read as.
enum Role : uint8_t { kSkip, kX, kY, kZ, kRed, kGreen, kBlue, kNx, kNy, kNz, kIntensity, kRoles };

// The spellings of three roles in a row (x, y, z; a colour; a normal), and of intensity.
struct Spelling {
  std::string_view names[3];
  Role first;
};

constexpr Spelling kSpellings[] = {{{"x", "y", "z"}, kX},     {{"red", "green", "blue"}, kRed},
                                   {{"r", "g", "b"}, kRed},   {{"diffuse_red", "diffuse_green", "diffuse_blue"}, kRed},
                                   {{"nx", "ny", "nz"}, kNx}, {{"normal_x", "normal_y", "normal_z"}, kNx}};
constexpr std::string_view kIntensityNames[] = {"intensity", "scalar_intensity", "scalar_Intensity"};

Role role_of(std::string_view name) {
  for (const Spelling& s : kSpellings)
    for (int k = 0; k < 3; ++k)
      if (s.names[k] == name) return static_cast<Role>(s.first + k);
  for (std::string_view n : kIntensityNames)
    if (n == name) return kIntensity;
  return kSkip;
}

// Rounded to the nearest integer, halves away from zero (as std::llround, inline); |d| <= INT32_MAX.
inline int32_t round_half_away(double d) {
  const int64_t t = static_cast<int64_t>(d);  // truncated
  const double frac = d - static_cast<double>(t);  // exact: t holds d's integer part
  return static_cast<int32_t>(t + (frac >= 0.5) - (frac <= -0.5));
}

// Rounded and clamped to [0, top]; NaN is 0.
uint16_t to_u16(double d, double top) {
  if (!(d > 0)) return 0;
  if (d >= top) return static_cast<uint16_t>(top);
  return static_cast<uint16_t>(round_half_away(d));
}

// As float, beyond its range as +-inf (a plain conversion of such a double is undefined).
float to_float(double d) {
  constexpr double kMax = std::numeric_limits<float>::max();
  if (d > kMax) return std::numeric_limits<float>::infinity();
  if (d < -kMax) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(d);
}

class PlyPoints final : public PointSource {
 public:
  PlyPoints(const std::string& path, const PointReadOptions& options) : path_(path) {
    Source first(path);
    header_ = detail::parse_header(first);
    find_layout();
    detail::check_counts(header_, path, first.size() - first.consumed(), vertex_el_ + 1);
    count_ = header_.elements[vertex_el_].count;
    // Where the first vertex record starts, for seeking to any of them (fixed-size records; else 0).
    vertex_offset_ = record_ == 0 ? 0 : detail::element_offset(header_, vertex_el_, first.consumed());
    const auto part = static_cast<unsigned __int128>(options.slice_part);
    const auto parts = static_cast<unsigned __int128>(std::max(options.slice_parts, 1));
    const auto lo = static_cast<uint64_t>(std::min<unsigned __int128>(count_ * part / parts, count_));
    const auto hi = static_cast<uint64_t>(std::min<unsigned __int128>(count_ * (part + 1) / parts, count_));
    sliced_ = vertex_offset_ != 0 && (lo > 0 || hi < count_);
    double max_abs = sliced_ ? slice_extent(first, lo, hi) : scan_extent(first);
    if (options.agree_extent) max_abs = options.agree_extent(max_abs);
    scale_ = ply_grid_scale(grid_kind(max_abs), max_abs);

    info_.format = "PLY " + detail::format_name(header_.format);
    info_.points = count_;
    info_.attributes = attributes_;
    std::fill(info_.scale, info_.scale + 3, scale_);
    info_.z_up = false;

    src_ = std::make_unique<Source>(path);
    detail::parse_header(*src_);
    with_values(*src_, [&](auto& v) { skip_elements_before_vertex(v); });
  }

  const PointCloudInfo& info() const override { return info_; }
  uint64_t records_read() const override { return next_; }
  bool read_whole_file() const override { return !sliced_; }

  uint64_t skip(uint64_t n) override {
    if (vertex_offset_ == 0) return PointSource::skip(n);
    n = std::min(n, count_ - next_);
    next_ += n;
    src_->seek(vertex_offset_ + next_ * record_);
    return n;
  }

  bool next(PointColumns& out, size_t max_points) override {
    if (max_points == 0) fail("next: max_points must be at least 1");
    if (next_ == count_) return false;
    const uint64_t n = std::min<uint64_t>(max_points, count_ - next_);
    reserve(out, n);
    if (next_fast(out, n)) {
      next_ += n;
      return true;
    }
    with_values(*src_, [&](auto& v) {
      walk(*src_, v, next_, n, [&](uint64_t i, const double* value) {
        for (int a = 0; a < 3; ++a) {
          const double q = coordinate(v, i, a, value) / scale_;
          if (!(std::fabs(q) <= std::numeric_limits<int32_t>::max()))  // only if the file changed since the first pass
            fail(v.where() + "vertex " + num(i) + " lies outside the grid of the first pass (was the file changed?)");
          out.xyz.push_back(round_half_away(q));
        }
        if (attributes_ & kPointRgb)
          for (int c = 0; c < 3; ++c) out.rgb.push_back(colour(kRed + c, value[kRed + c]));
        if (attributes_ & kPointNormal)
          for (int c = 0; c < 3; ++c) out.normal.push_back(to_float(value[kNx + c]));
        if (attributes_ & kPointIntensity) out.intensity.push_back(to_u16(value[kIntensity], 65535));
      });
    });
    next_ += n;
    return true;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }
  [[noreturn]] void fail_at(uint64_t line, const std::string& what) const { fail("line " + num(line) + ": " + what); }

  [[noreturn]] void truncated(uint64_t complete) const {
    fail("truncated: expected " + num(count_) + " vertices, file ends after " + num(complete));
  }

  // Which vertex properties are read as what, the attributes that gives, and the binary record layout.
  void find_layout() {
    const auto& els = header_.elements;
    vertex_el_ =
        std::find_if(els.begin(), els.end(), [](const Element& e) { return e.name == "vertex"; }) - els.begin();
    if (vertex_el_ == els.size()) fail("no 'vertex' element");
    const Element& ve = els[vertex_el_];
    bool seen[kRoles] = {};
    roles_.assign(ve.props.size(), kSkip);
    record_ = 0;
    for (size_t k = 0; k < ve.props.size(); ++k) {
      const Property& p = ve.props[k];
      const Role role = role_of(p.name);
      if (role != kSkip && !seen[role]) {  // a second alias of a role read already is skipped
        if (p.is_list) fail_at(p.line, "vertex property '" + p.name + "' is a list");
        seen[role] = true;
        roles_[k] = role;
        type_[role] = p.type;
        offset_[role] = record_;
      }
      record_ = p.is_list || record_ == SIZE_MAX ? SIZE_MAX : record_ + scalar_size(p.type);
    }
    if (record_ > 4096) record_ = 0;  // lists, or records too large for the fast path (the buffer holds 4096 bytes)
    for (Role r : {kX, kY, kZ})
      if (!seen[r]) fail_at(ve.line, "element 'vertex' has no property '" + std::string(1, "xyz"[r - kX]) + "'");
    attributes_ = 0;
    if (group(seen, kRed)) attributes_ |= kPointRgb;
    if (group(seen, kNx)) attributes_ |= kPointNormal;
    if (seen[kIntensity]) attributes_ |= kPointIntensity;
    for (int r = kX; r < kRoles; ++r)
      if (seen[r]) present_.push_back(static_cast<Role>(r));
  }

  // True if all three roles from `first` are read; a partial set (a lone "r" may be a radius) is skipped.
  bool group(bool* seen, Role first) {
    if (seen[first] && seen[first + 1] && seen[first + 2]) return true;
    for (Role& r : roles_)
      if (r >= first && r < first + 3) r = kSkip;
    std::fill(seen + first, seen + first + 3, false);
    return false;
  }

  // The first pass over vertices [first, last) alone, reached by seeking.
  double slice_extent(Source& src, uint64_t first, uint64_t last) const {
    double max_abs = 0;
    src.seek(vertex_offset_ + first * record_);
    with_values(src, [&](auto& v) {
      walk(src, v, first, last - first, [&](uint64_t i, const double* value) {
        for (int a = 0; a < 3; ++a) max_abs = std::max(max_abs, std::fabs(coordinate(v, i, a, value)));
      });
    });
    return max_abs;
  }

  // The first pass: the largest |coordinate|, every coordinate checked finite.
  double scan_extent(Source& src) const {
    double max_abs = 0;
    bool fast = false, again = false;
    with_values(src, [&](auto& v) {
      skip_elements_before_vertex(v);
      if constexpr (std::decay_t<decltype(v)>::kBinary) {
        const Extent e = fast_extent<std::decay_t<decltype(v)>::kSwap>(src, max_abs);
        fast = e == Extent::found;
        again = e == Extent::not_finite;
        if (fast || again) return;
      }
      extent_walk(src, v, max_abs);
    });
    if (again) {  // a coordinate is not finite: the generic walk over a fresh read names it
      Source fresh(path_);
      detail::parse_header(fresh);
      with_values(fresh, [&](auto& v) {
        skip_elements_before_vertex(v);
        extent_walk(fresh, v, max_abs);
      });
    }
    return max_abs;
  }

  template <class V>
  void extent_walk(Source& src, V& v, double& max_abs) const {
    max_abs = 0;
    walk(src, v, 0, count_, [&](uint64_t i, const double* value) {
      for (int a = 0; a < 3; ++a) max_abs = std::max(max_abs, std::fabs(coordinate(v, i, a, value)));
    });
  }

  // The first pass's fast path (the layouts next_fast reads): not_applicable having read nothing; not_finite
  // having read the vertices, when a coordinate is inf or NaN (the generic walk then names it).
  enum class Extent { not_applicable, found, not_finite };
  template <bool Swap>
  Extent fast_extent(Source& src, double& max_abs) const {
    if (record_ == 0 || type_[kY] != type_[kX] || type_[kZ] != type_[kX]) return Extent::not_applicable;
    if (type_[kX] == Scalar::f32) return extent_records<float, Swap>(src, max_abs);
    if (type_[kX] == Scalar::f64) return extent_records<double, Swap>(src, max_abs);
    return Extent::not_applicable;
  }

  template <class T, bool Swap>
  Extent extent_records(Source& copy, double& max_abs) const {
    // IEEE magnitudes order as their bit patterns without the sign: a branch-free integer maximum, and any
    // inf or NaN makes it at least the exponent mask.
    using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
    constexpr Bits kMagnitude = ~Bits{0} >> 1;
    constexpr Bits kExponent = std::bit_cast<Bits>(std::numeric_limits<T>::infinity());
    Bits m = 0;
    for (uint64_t i = 0; i < count_;) {
      auto [begin, stop] = copy.window(record_);
      const uint64_t k = std::min<uint64_t>(count_ - i, static_cast<uint64_t>(stop - begin) / record_);
      if (k == 0) truncated(i);
      const char* r = begin;
      for (uint64_t j = 0; j < k; ++j, r += record_)
        for (int a = 0; a < 3; ++a) {
          const Bits b = std::bit_cast<Bits>(detail::load<T, Swap>(r + offset_[kX + a])) & kMagnitude;
          m = b > m ? b : m;
        }
      copy.advance(k * record_);
      i += k;
    }
    if (m >= kExponent) return Extent::not_finite;
    max_abs = static_cast<double>(std::bit_cast<T>(m));
    return Extent::found;
  }

  PlyGrid grid_kind(double max_abs) const {
    bool integers = true, single = true;
    for (Role r : {kX, kY, kZ}) {
      integers = integers && is_integer(type_[r]);
      single = single && (type_[r] == Scalar::f32 || (is_integer(type_[r]) && scalar_size(type_[r]) <= 2));
    }
    if (integers && max_abs < 2147483648.0) return PlyGrid::integer;
    return single ? PlyGrid::float32 : PlyGrid::float64;
  }

  // Coordinate `axis` of vertex i, at its property's precision (ascii floats are parsed as double), finite.
  template <class V>
  double coordinate(const V& v, uint64_t i, int axis, const double* value) const {
    const Role r = static_cast<Role>(kX + axis);
    const double c = type_[r] == Scalar::f32 ? to_float(value[r]) : value[r];
    if (!std::isfinite(c)) [[unlikely]]
      fail(v.where() + "vertex " + num(i) + ": coordinate " + std::string(1, "xyz"[axis]) + " = " + std::to_string(c) +
           " is not finite");
    return c;
  }

  uint16_t colour(int role, double d) const {
    return is_integer(type_[role]) ? to_u16(d, 65535) : to_u16(255 * d, 255);
  }

  void reserve(PointColumns& out, uint64_t n) const { out.reserve_more(n, attributes_, 0); }

  // Runs f with the value reader of the file's format.
  template <class F>
  void with_values(Source& src, F&& f) const {
    constexpr bool host_le = std::endian::native == std::endian::little;
    if (header_.format == Format::ascii) {
      detail::AsciiValues v(src);
      f(v);
    } else if ((header_.format == Format::binary_le) == host_le) {
      detail::BinaryValues<false> v(src);
      f(v);
    } else {
      detail::BinaryValues<true> v(src);
      f(v);
    }
  }

  template <class V>
  uint64_t list_length(V& v, const Element& e, uint64_t i, const Property& p) const {
    const double n = v.scalar(p.count_type);
    if (n < 0)
      fail(v.where() + e.name + " " + num(i) + ": list '" + p.name + "' has negative length " +
           std::to_string(static_cast<int64_t>(n)));
    return static_cast<uint64_t>(n);
  }

  template <class V>
  void skip_property(V& v, const Element& e, uint64_t i, const Property& p) const {
    v.skip(p.type, p.is_list ? list_length(v, e, i, p) : 1);
  }

  template <class V>
  void skip_elements_before_vertex(V& v) const {
    for (size_t k = 0; k < vertex_el_; ++k) {
      const Element& e = header_.elements[k];
      if (e.props.empty()) continue;  // no data, however large the count
      uint64_t i = 0;
      try {
        for (; i < e.count; ++i)
          for (const Property& p : e.props) skip_property(v, e, i, p);
      } catch (const EndOfData&) {
        fail("truncated: expected " + num(e.count) + " " + detail::plural(e) + ", file ends after " + num(i));
      }
    }
  }

  // Calls f(i, value) for vertices [first, first + n), value[role] holding each role's value as double.
  template <class V, class F>
  void walk(Source& src, V& v, uint64_t first, uint64_t n, F&& f) const {
    const Element& e = header_.elements[vertex_el_];
    double value[kRoles] = {};
    const uint64_t end = first + n;
    if constexpr (V::kBinary) {
      if (record_ != 0) {  // fast path: whole records decoded straight from the buffer
        for (uint64_t i = first; i < end;) {
          auto [begin, stop] = src.window(record_);
          const uint64_t k = std::min<uint64_t>(end - i, static_cast<uint64_t>(stop - begin) / record_);
          if (k == 0) truncated(i);
          for (const char* r = begin; r != begin + k * record_; r += record_, ++i) {
            for (Role role : present_) value[role] = decode<V::kSwap>(r + offset_[role], type_[role]);
            f(i, value);
          }
          src.advance(k * record_);
        }
        return;
      }
    }
    uint64_t i = first;
    try {
      for (; i < end; ++i) {
        for (size_t k = 0; k < e.props.size(); ++k) {
          if (roles_[k] == kSkip)
            skip_property(v, e, i, e.props[k]);
          else
            value[roles_[k]] = v.scalar(e.props[k].type);
        }
        f(i, value);
      }
    } catch (const EndOfData&) {
      truncated(i);
    }
  }

  // The fast path of binary records whose x, y and z share one type: each batch decoded straight into the
  // columns with the coordinates' type known to the compiler (a plain loop instead of a switch and a double per
  // value). Same values as the generic walk; false where it does not apply.
  bool next_fast(PointColumns& out, uint64_t n) {
    if (header_.format == Format::ascii || record_ == 0 || type_[kY] != type_[kX] || type_[kZ] != type_[kX])
      return false;
    constexpr bool host_le = std::endian::native == std::endian::little;
    const bool swap = (header_.format == Format::binary_le) != host_le;
    switch (type_[kX]) {
      case Scalar::f32: swap ? fast_records<float, true>(out, n) : fast_records<float, false>(out, n); return true;
      case Scalar::f64: swap ? fast_records<double, true>(out, n) : fast_records<double, false>(out, n); return true;
      default: return false;
    }
  }

  template <class T, bool Swap>
  void fast_records(PointColumns& out, uint64_t n) {
    const size_t base = out.size();
    out.xyz.resize(3 * (base + n));
    if (attributes_ & kPointRgb) out.rgb.resize(3 * (base + n));
    if (attributes_ & kPointNormal) out.normal.resize(3 * (base + n));
    if (attributes_ & kPointIntensity) out.intensity.resize(base + n);
    const double inv = 1 / scale_;  // scale_ is a power of two: multiplying by its inverse divides exactly
    const bool exact_inverse = std::isfinite(inv) && inv * scale_ == 1;
    for (uint64_t i = 0; i < n;) {
      auto [begin, stop] = src_->window(record_);
      const uint64_t k = std::min<uint64_t>(n - i, static_cast<uint64_t>(stop - begin) / record_);
      if (k == 0) truncated(next_ + i);
      const char* r = begin;
      int32_t* xyz = out.xyz.data() + 3 * (base + i);
      for (uint64_t j = 0; j < k; ++j, r += record_) {
        for (int a = 0; a < 3; ++a) {
          const double c = detail::load<T, Swap>(r + offset_[kX + a]);
          const double q = exact_inverse ? c * inv : c / scale_;
          if (!(std::fabs(q) <= std::numeric_limits<int32_t>::max())) [[unlikely]] {
            if (!std::isfinite(c))
              fail("vertex " + num(next_ + i + j) + ": coordinate " + std::string(1, "xyz"[a]) + " = " +
                   std::to_string(c) + " is not finite");
            fail("vertex " + num(next_ + i + j) + " lies outside the grid of the first pass (was the file changed?)");
          }
          xyz[3 * j + a] = round_half_away(q);
        }
      }
      if (attributes_ != 0) fast_attributes<Swap>(out, base + i, begin, k);
      src_->advance(k * record_);
      i += k;
    }
  }

  template <bool Swap>
  void fast_attributes(PointColumns& out, uint64_t at, const char* r, uint64_t k) const {
    const bool rgb8 = (attributes_ & kPointRgb) && type_[kRed] == Scalar::u8 && type_[kGreen] == Scalar::u8 &&
                      type_[kBlue] == Scalar::u8;  // the common case: bytes as they are
    if (rgb8) {
      uint16_t* rgb = out.rgb.data() + 3 * at;
      const char* q = r;
      for (uint64_t j = 0; j < k; ++j, q += record_)
        for (int c = 0; c < 3; ++c) rgb[3 * j + c] = static_cast<uint8_t>(q[offset_[kRed + c]]);
      if ((attributes_ & ~kPointRgb) == 0) return;
    }
    for (uint64_t j = 0; j < k; ++j, r += record_) {
      if ((attributes_ & kPointRgb) && !rgb8)
        for (int c = 0; c < 3; ++c)
          out.rgb[3 * (at + j) + c] = colour(kRed + c, decode<Swap>(r + offset_[kRed + c], type_[kRed + c]));
      if (attributes_ & kPointNormal)
        for (int c = 0; c < 3; ++c)
          out.normal[3 * (at + j) + c] = to_float(decode<Swap>(r + offset_[kNx + c], type_[kNx + c]));
      if (attributes_ & kPointIntensity)
        out.intensity[at + j] = to_u16(decode<Swap>(r + offset_[kIntensity], type_[kIntensity]), 65535);
    }
  }

  std::string path_;
  Header header_;
  size_t vertex_el_ = 0;
  uint64_t count_ = 0;
  std::vector<Role> roles_;    // per vertex property
  std::vector<Role> present_;  // the roles read
  Scalar type_[kRoles] = {};
  size_t offset_[kRoles] = {};  // bytes into a binary record
  size_t record_ = 0;           // bytes per binary vertex record; 0 if the fast path cannot read it
  uint32_t attributes_ = 0;
  double scale_ = 1;
  PointCloudInfo info_;
  std::unique_ptr<Source> src_;  // the second pass
  uint64_t next_ = 0;
  uint64_t vertex_offset_ = 0;  // byte of the first vertex record, where records can be sought (else 0)
  bool sliced_ = false;         // the first pass read a slice of the vertices alone
};

}  // namespace

double ply_grid_scale(PlyGrid grid, double max_abs) {
  if (grid == PlyGrid::integer || max_abs == 0) return 1;
  int e = 0;
  std::frexp(max_abs, &e);  // max_abs = f * 2^e, 0.5 <= f < 1
  // The smallest double (2^-1074) bounds the scale of subnormal coordinates.
  return std::ldexp(1.0, std::max(e - (grid == PlyGrid::float32 ? 24 : 30), -1074));
}

std::unique_ptr<PointSource> open_ply_points(const std::string& path, const PointReadOptions& options) {
  return std::make_unique<PlyPoints>(path, options);
}

}  // namespace mv::io

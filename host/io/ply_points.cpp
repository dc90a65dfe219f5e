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

// Rounded and clamped to [0, top]; NaN is 0.
uint16_t to_u16(double d, double top) {
  if (!(d > 0)) return 0;
  if (d >= top) return static_cast<uint16_t>(top);
  return static_cast<uint16_t>(std::lround(d));
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
  PlyPoints(const std::string& path, const PointReadOptions&) : path_(path) {
    Source first(path);
    header_ = detail::parse_header(first);
    find_layout();
    detail::check_counts(header_, path, first.size() - first.consumed(), vertex_el_ + 1);
    count_ = header_.elements[vertex_el_].count;
    const double max_abs = scan_extent(first);
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

  bool next(PointColumns& out, size_t max_points) override {
    if (max_points == 0) fail("next: max_points must be at least 1");
    if (next_ == count_) return false;
    const uint64_t n = std::min<uint64_t>(max_points, count_ - next_);
    reserve(out, n);
    with_values(*src_, [&](auto& v) {
      walk(*src_, v, next_, n, [&](uint64_t i, const double* value) {
        for (int a = 0; a < 3; ++a) {
          const double q = coordinate(v, i, a, value) / scale_;
          if (!(std::fabs(q) <= std::numeric_limits<int32_t>::max()))  // only if the file changed since the first pass
            fail(v.where() + "vertex " + num(i) + " lies outside the grid of the first pass (was the file changed?)");
          out.xyz.push_back(static_cast<int32_t>(std::llround(q)));
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

  // The first pass: the largest |coordinate|, every coordinate checked finite.
  double scan_extent(Source& src) const {
    double max_abs = 0;
    with_values(src, [&](auto& v) {
      skip_elements_before_vertex(v);
      walk(src, v, 0, count_, [&](uint64_t i, const double* value) {
        for (int a = 0; a < 3; ++a) max_abs = std::max(max_abs, std::fabs(coordinate(v, i, a, value)));
      });
    });
    return max_abs;
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

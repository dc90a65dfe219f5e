// The PLY reader: the layout it accepts (a vertex element with x, y, z, an optional face element after it
// with an integer index list, counts the file can hold), and PlyMeshReader over the element walker
// (ply_walker.h), instantiated here for the value reader of each format.
#include "ply_reader.h"

#include <string>
#include <string_view>

#include "megavox/error.h"
#include "ply_walker.h"

namespace mv::io {

PlyMeshReader::Impl::Impl(const std::string& path, uint64_t ram, bool defer_vertices)
    : src(path), header(detail::parse_header(src)), ram_bytes(ram) {
  check_counts();
  find_layout();
  info = {header.elements[vertex_el].count, face_el == kNone ? 0 : header.elements[face_el].count,
          detail::format_name(header.format), header.comments};
  vertex_limit = static_cast<double>(info.vertices);
  // Deferred: the vertices' and the faces' first bytes, where every element before the faces has fixed-size
  // records (and the vertices' fit the fast path's buffer).
  const uint64_t faces_at =
      defer_vertices && face_el != kNone ? detail::element_offset(header, face_el, src.consumed()) : 0;
  if (faces_at != 0 && record_bytes(header.elements[vertex_el]) != 0) {
    vertex_offset = detail::element_offset(header, vertex_el, src.consumed());
    src.seek(faces_at);
    next_el = face_el;
    vertices_deferred = true;
    return;
  }
  with_values([&](auto& v) { advance(v); });
}

PlyMeshReader::Impl::~Impl() { TempFile::unmap(mapped, pos.size_bytes()); }

void PlyMeshReader::Impl::fail(const std::string& what) const { throw Error(src.path() + ": " + what); }

void PlyMeshReader::Impl::fail_at(uint64_t line, const std::string& what) const {
  fail("line " + num(line) + ": " + what);
}

size_t PlyMeshReader::Impl::find_property(const Element& e, std::string_view name) {
  for (size_t i = 0; i < e.props.size(); ++i)
    if (e.props[i].name == name) return i;
  return kNone;
}

void PlyMeshReader::Impl::find_layout() {
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
  // Colours: red, green and blue, all uchar or ushort; other types (float colours) are not read.
  size_t channel[3] = {find_property(ve, "red"), find_property(ve, "green"), find_property(ve, "blue")};
  bool colour = true;
  for (size_t c : channel)
    colour = colour && c != kNone && !ve.props[c].is_list &&
             (ve.props[c].type == Scalar::u8 || ve.props[c].type == Scalar::u16);
  if (colour)
    for (int k = 0; k < 3; ++k) {
      vertex_role[channel[k]] = 3 + k;
      colour_wide = colour_wide || ve.props[channel[k]].type == Scalar::u16;
    }
  colour_roles = colour;
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

void PlyMeshReader::Impl::check_counts() const {
  detail::check_counts(header, src.path(), src.size() - src.consumed());
}

void PlyMeshReader::Impl::truncated(const Element& e, uint64_t complete) const {
  fail("truncated: expected " + num(e.count) + " " + detail::plural(e) + ", file ends after " + num(complete));
}

size_t PlyMeshReader::Impl::record_bytes(const Element& e) {
  size_t bytes = 0;
  for (const Property& p : e.props) {
    if (p.is_list) return 0;
    bytes += scalar_size(p.type);
  }
  return bytes <= 4096 ? bytes : 0;  // the source buffer holds at least 4096 bytes
}

PlyMeshReader::PlyMeshReader(const std::string& path, uint64_t ram_bytes, bool defer_vertices)
    : impl_(std::make_unique<Impl>(path, ram_bytes, defer_vertices)) {}
PlyMeshReader::~PlyMeshReader() = default;
PlyMeshReader::PlyMeshReader(PlyMeshReader&&) noexcept = default;
PlyMeshReader& PlyMeshReader::operator=(PlyMeshReader&&) noexcept = default;

const PlyInfo& PlyMeshReader::info() const { return impl_->info; }

std::span<const float> PlyMeshReader::positions() const { return impl_->pos; }
std::span<const uint32_t> PlyMeshReader::colours() const { return impl_->colours; }
bool PlyMeshReader::positions_mapped() const { return impl_->mapped != nullptr; }

bool PlyMeshReader::next_triangles(std::vector<uint32_t>& indices, size_t max_triangles) {
  indices.clear();
  if (max_triangles == 0) impl_->fail("next_triangles: max_triangles must be at least 1");
  if (impl_->done) return false;
  impl_->with_values([&](auto& v) { impl_->stream_faces(v, indices, max_triangles); });
  return !indices.empty();
}

bool PlyMeshReader::select_faces(uint64_t first, uint64_t last) {
  Impl& m = *impl_;
  if (m.face_el == Impl::kNone || m.header.format == detail::Format::ascii || m.next_el != m.face_el || m.face != 0 ||
      m.poly_left != 0)
    return false;
  const Element& e = m.header.elements[m.face_el];
  if (e.props.size() != 1 || first > last || last > e.count) return false;
  const Property& ip = e.props[m.index_prop];
  const uint64_t record = scalar_size(ip.count_type) + 3 * scalar_size(ip.type);
  m.face_start = m.src.consumed();
  m.src.seek(m.face_start + first * record);
  m.face = first;
  m.face_end = last;
  m.triangles_only = true;
  m.share_bytes = (last - first) * record;
  m.spanned = m.face_start + m.share_bytes;
  return true;
}

uint64_t PlyMeshReader::bytes_spanned() const {
  const Impl& m = *impl_;
  if (m.vertices_deferred) return m.vertex_offset + m.vertex_bytes_read + m.share_bytes;
  return m.spanned ? m.spanned : m.src.size();
}

bool PlyMeshReader::vertices_deferred() const { return impl_->vertices_deferred; }
int PlyMeshReader::colour_bits() const { return impl_->colour_roles ? (impl_->colour_wide ? 16 : 8) : 0; }

void PlyMeshReader::read_vertex_range(uint64_t first, uint64_t last, std::vector<float>& xyz, std::vector<uint16_t>& rgb) {
  Impl& m = *impl_;
  const Element& e = m.header.elements[m.vertex_el];
  if (!m.vertices_deferred || first > last || last > e.count) m.fail("read_vertex_range: not a range of deferred vertices");
  const size_t record = Impl::record_bytes(e);
  Source from(m.src.path());
  from.seek(m.vertex_offset + first * record);
  xyz.resize(3 * (last - first));
  rgb.resize(m.colour_roles ? 3 * (last - first) : 0);
  m.with_values_on(from, [&](auto& v) {
    if constexpr (std::decay_t<decltype(v)>::kBinary)
      m.read_vertex_records(v, from, e, record, first, last - first, xyz.data(), rgb.data());
  });
  m.vertex_bytes_read += (last - first) * record;
}

}  // namespace mv::io

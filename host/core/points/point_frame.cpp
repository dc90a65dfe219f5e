#include "point_frame.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "megavox/error.h"

namespace mv::points {

namespace {

struct Vec {
  double x = 0, y = 0, z = 0;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(Vec a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vec unit(Vec a) { return a * (1 / std::sqrt(dot(a, a))); }
double& at(Vec& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }
double get(const Vec& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

// The up direction in model units: the option's, else the file's (+Z for LAS input, +Y for PLY).
Vec up_direction(const PointHierarchy& h, const PointRenderOptions& o) {
  if (!o.up) return h.source.z_up ? Vec{0, 0, 1} : Vec{0, 1, 0};
  const Vec v{(*o.up)[0], (*o.up)[1], (*o.up)[2]};
  if (!(dot(v, v) > 0) || !std::isfinite(dot(v, v)))
    throw CodedError(ErrorCode::invalid_argument, "points render: the up direction must be a direction, not 0,0,0",
                     setting_up);
  return v;
}

// The axis nearest a direction.
int nearest_axis(Vec v) {
  const double m[3] = {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)};
  return m[2] > m[0] && m[2] > m[1] ? 2 : m[1] > m[0] ? 1 : 0;
}

// A simple colour ramp for clouds without colour: deep blue, teal, yellow.
void ramp(double t, uint8_t* rgb) {
  t = std::clamp(t, 0.0, 1.0);
  const double stops[3][3] = {{40, 60, 160}, {40, 170, 150}, {250, 220, 60}};
  const double f = t * 2;
  const int i = std::min(1, static_cast<int>(f));
  const double w = f - i;
  for (int c = 0; c < 3; ++c) rgb[c] = static_cast<uint8_t>(stops[i][c] * (1 - w) + stops[i + 1][c] * w + 0.5);
}

}  // namespace

FrameBox points_box(const PointColumns& points) {
  FrameBox b{};
  if (points.xyz.empty()) return b;
  for (int a = 0; a < 3; ++a) b.lo[a] = b.hi[a] = points.xyz[a];
  for (size_t i = 0; i < points.xyz.size(); i += 3)
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min<int64_t>(b.lo[a], points.xyz[i + a]);
      b.hi[a] = std::max<int64_t>(b.hi[a], points.xyz[i + a]);
    }
  return b;
}

namespace {

// The camera a frame's options give, in scaled cells.
struct Camera {
  Vec lo, hi;  // the framed box
  Vec eye, cam_x, cam_y, fwd;
  double aspect[3];
  double focal, dist, radius, half;
  int up;
};

Camera make_camera(const PointHierarchy& h, const PointRenderOptions& o, const FrameBox* frame_box) {
  Camera cam;
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw Error("points render: the image must be 1-16384 pixels wide and high, not " + std::to_string(o.width) + "x" +
                std::to_string(o.height));
  if (!(o.fov > 1 && o.fov < 170))
    throw CodedError(ErrorCode::invalid_argument, "points render: the field of view must lie between 1 and 170 degrees",
                     setting_fov);
  if (!(o.lod_pixels >= 0)) throw CodedError(ErrorCode::invalid_argument,
                   "points render: the level-of-detail pixel size must be 0 or more",
                                                 setting_lod_pixels);
  // Camera space in cells scaled per axis by the input's scale over the largest (the cube is square in input
  // units, which LAS may scale differently per axis).
  const double smax = std::max({std::fabs(h.source.scale[0]), std::fabs(h.source.scale[1]), std::fabs(h.source.scale[2])});
  double* aspect = cam.aspect;
  for (int a = 0; a < 3; ++a) aspect[a] = std::fabs(h.source.scale[a]) / smax;
  // The framed box, in scaled cells.
  const FrameBox box = frame_box ? *frame_box : points_box(h.points);
  Vec& lo = cam.lo;
  Vec& hi = cam.hi;
  for (int a = 0; a < 3; ++a) {
    auto to_cell = [&](int64_t v) { return std::ldexp(double(v - h.cube_min[a]), -h.shift) * aspect[a]; };
    at(lo, a) = to_cell(box.lo[a]);
    at(hi, a) = to_cell(box.hi[a]);
  }
  const Vec centre = (lo + hi) * 0.5;
  const double radius = cam.radius = std::max(1.0, std::sqrt(dot(hi - lo, hi - lo)) * 0.5);
  // Model units to scaled cells: world = offset + scale * xyz; a direction keeps its sense per axis.
  auto point_to_cell = [&](const std::array<double, 3>& p) {
    Vec c;
    for (int a = 0; a < 3; ++a)
      at(c, a) =
          std::ldexp((p[a] - h.source.offset[a]) / h.source.scale[a] - double(h.cube_min[a]), -h.shift) * aspect[a];
    return c;
  };
  Vec upv = up_direction(h, o);
  for (int a = 0; a < 3; ++a)
    if (h.source.scale[a] < 0) at(upv, a) = -get(upv, a);
  upv = unit(upv);
  const int up = cam.up = nearest_axis(upv);
  const double half = cam.half = o.fov * M_PI / 360;
  Vec target = centre, cam_up = upv;
  if (o.eye) {
    if (o.target) target = point_to_cell(*o.target);
    cam.eye = point_to_cell(*o.eye);
  } else {
    if (o.target)
      throw CodedError(ErrorCode::invalid_argument, "points render: a target needs an eye (or use a preset view)",
                       setting_target | setting_eye);
    // The front view's direction towards the eye and its right, for the axis nearest up, made square to up.
    Vec toward;
    if (up == 2) at(toward, 1) = -1;  // z up: front from -Y
    else at(toward, (up + 1) % 3) = 1;  // y up: from +Z; x up: from +Y
    toward = unit(toward - upv * dot(toward, upv));
    const Vec right_v = cross(upv, toward);
    Vec dir;  // from the target to the eye
    if (o.view == "front") dir = toward;
    else if (o.view == "back") dir = toward * -1;
    else if (o.view == "right") dir = right_v;
    else if (o.view == "left") dir = right_v * -1;
    else if (o.view == "top") dir = upv;
    else if (o.view == "iso") dir = unit(toward + right_v * 0.8 + upv * 0.7);
    else
      throw CodedError(ErrorCode::invalid_argument,
                       "points render: unknown view '" + o.view + "' (front, back, left, right, top, iso)",
                       setting_view);
    cam.eye = centre + dir * (radius / std::sin(half) * 1.02);
    if (o.view == "top") cam_up = toward * -1;
  }
  // The depth range covers the framed box from the eye.
  cam.dist = std::sqrt(dot(centre - cam.eye, centre - cam.eye));
  const Vec view = target - cam.eye;
  if (!(dot(view, view) > 0))
    throw CodedError(ErrorCode::invalid_argument, "points render: the eye and the target are the same point",
                     setting_eye | setting_target);
  cam.fwd = unit(view);
  const Vec side = cross(cam.fwd, cam_up);
  if (!(dot(side, side) > 1e-12))
    throw CodedError(ErrorCode::invalid_argument, "points render: the up direction points along the view; give another",
                     setting_up);
  cam.cam_x = unit(side);
  cam.cam_y = cross(cam.cam_x, cam.fwd);
  cam.focal = (o.height / 2.0) / std::tan(half);
  return cam;
}

// The cut's rule: a node is drawn instead of its children when its points' spacing (its side over its grid)
// projects to at most lod pixels; lod 0: never.
bool fine_enough(const Camera& cam, uint32_t grid_bits, double lod, uint32_t level, uint64_t prefix) {
  if (!(lod > 0)) return false;
  const double side = std::ldexp(1.0, 21 - static_cast<int>(level));
  Vec c;
  for (int a = 0; a < 3; ++a) {
    uint32_t v = 0;
    for (uint32_t b = 0; b < level; ++b) v |= static_cast<uint32_t>((prefix >> (3 * b + a)) & 1) << b;
    at(c, a) = (v + 0.5) * side * cam.aspect[a];
  }
  const double d = std::sqrt(dot(c - cam.eye, c - cam.eye)) - side * 0.87;
  const double spacing = side / std::ldexp(1.0, static_cast<int>(grid_bits));
  return d > 0 && cam.focal * spacing / d <= lod;
}

}  // namespace

// Camera lives in this file's anonymous namespace; GCC takes a .cpp included into a unity batch for a header
// and warns that Impl (declared in one) holds it. Impl is defined here only, so nothing else can see it.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsubobject-linkage"
struct LodRule::Impl {
  Camera cam;
  uint32_t grid_bits;
  double lod;
};
#pragma GCC diagnostic pop

LodRule::LodRule(const PointHierarchy& grid, const PointRenderOptions& options, const FrameBox& box)
    : impl_(std::make_unique<Impl>(Impl{make_camera(grid, options, &box), grid.grid_bits, options.lod_pixels})) {}
LodRule::~LodRule() = default;
LodRule::LodRule(LodRule&&) noexcept = default;

bool LodRule::fine_enough(uint32_t level, uint64_t prefix) const {
  return points::fine_enough(impl_->cam, impl_->grid_bits, impl_->lod, level, prefix);
}

SplatFrame splat_frame(const PointHierarchy& h, const PointRenderOptions& o, const std::vector<uint32_t>& roots,
                       const FrameBox* frame_box) {
  if (h.nodes.empty()) throw Error("points render: the hierarchy has no nodes");
  const Camera cam = make_camera(h, o, frame_box);
  const Vec &lo = cam.lo, &hi = cam.hi, &eye = cam.eye, &fwd = cam.fwd, &cam_x = cam.cam_x, &cam_y = cam.cam_y;
  const double* aspect = cam.aspect;
  const double dist = cam.dist, radius = cam.radius, focal = cam.focal;
  const int up = cam.up;
  auto cell = [&](uint64_t p, int a) { return h.cell(p, a); };

  SplatFrame f;
  MvSplatParams& p = f.params;
  p.width = o.width;
  p.height = o.height;
  p.radius = std::max(1u, o.point_size) / 2;
  p.focal_q8 = static_cast<uint32_t>(std::llround(focal * 256));
  p.cx_q8 = static_cast<int32_t>(o.width * 128);
  p.cy_q8 = static_cast<int32_t>(o.height * 128);
  for (int a = 0; a < 3; ++a)
    if (std::fabs(get(eye, a) / aspect[a]) > 2e9) throw Error("points render: the camera is too far from the cloud");
  p.eye_x = static_cast<int32_t>(std::llround(eye.x / aspect[0]));
  p.eye_y = static_cast<int32_t>(std::llround(eye.y / aspect[1]));
  p.eye_z = static_cast<int32_t>(std::llround(eye.z / aspect[2]));
  const Vec rows[3] = {cam_x, cam_y, fwd};
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) {
      p.rot[3 * r + a] = static_cast<int32_t>(std::llround(get(rows[r], a) * aspect[a] * double(1 << 30)));
    }
  p.near_q14 = 1u << 14;
  const double far_q14 = (dist + radius) * 16384 * 2;
  p.depth_shift = 0;
  while (far_q14 / std::ldexp(1.0, static_cast<int>(p.depth_shift)) >= 4e9) ++p.depth_shift;

  // The cut: from the root down, a node is drawn when it is a leaf or its points' spacing (its side over its
  // grid) projects to at most lod_pixels; else its children are visited.
  const double lod = o.lod_pixels;  // 0: leaves only
  std::vector<uint32_t> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    const PointNode& n = h.nodes[i];
    const uint64_t prefix = n.code ^ (uint64_t{1} << (3 * n.level));
    const bool draw = n.leaf() || fine_enough(cam, h.grid_bits, lod, n.level, prefix);
    if (draw) {
      f.nodes.push_back(i);
      continue;
    }
    // Children in reverse so that they pop in octant order (the cut's order does not change the picture).
    uint32_t k = n.first_child + static_cast<uint32_t>(__builtin_popcount(n.child_mask));
    while (k > n.first_child) stack.push_back(--k);
  }
  std::sort(f.nodes.begin(), f.nodes.end());

  // The cut's points and colours.
  const bool rgb = !h.points.rgb.empty();
  uint16_t rgb_max = 0;
  if (rgb) rgb_max = *std::max_element(h.points.rgb.begin(), h.points.rgb.end());
  const int rgb_shift = rgb_max > 255 ? 8 : 0;
  uint16_t imax = 1;
  if (!h.points.intensity.empty()) imax = std::max<uint16_t>(1, *std::max_element(h.points.intensity.begin(), h.points.intensity.end()));
  for (uint32_t i : f.nodes) {
    const PointNode& n = h.nodes[i];
    for (uint64_t q = n.first_point; q < n.first_point + n.point_count; ++q) {
      for (int a = 0; a < 3; ++a) f.cells.push_back(cell(q, a));
      uint8_t c[3];
      if (rgb) {
        for (int k = 0; k < 3; ++k) c[k] = static_cast<uint8_t>(h.points.rgb[3 * q + k] >> rgb_shift);
      } else if (!h.points.intensity.empty()) {
        c[0] = c[1] = c[2] = static_cast<uint8_t>(std::min(255.0, 40 + 215.0 * h.points.intensity[q] / imax));
      } else {
        ramp((cell(q, up) * aspect[up] - get(lo, up)) / std::max(1.0, get(hi, up) - get(lo, up)), c);
      }
      f.colours.insert(f.colours.end(), c, c + 3);
    }
  }
  return f;
}

Image resolve_frame(const SplatFrame& frame, const std::vector<uint32_t>& depth, const std::vector<uint32_t>& index,
                    uint64_t* covered) {
  const uint32_t w = frame.params.width, h = frame.params.height;
  Image img;
  img.width = w;
  img.height = h;
  img.rgb.assign(size_t{w} * h * 3, 0);
  uint64_t count = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t at = size_t{y} * w + x;
      uint8_t* px = &img.rgb[at * 3];
      if (index[at] == MV_SPLAT_EMPTY) {
        px[0] = 24, px[1] = 26, px[2] = 32;
        continue;
      }
      ++count;
      // Eye-dome lighting: how far the neighbours lie in front of this pixel, in log depth.
      const double ld = std::log2(double(depth[at]) + 1);
      double obscured = 0;
      const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int nx = int(x) + 2 * dx[k], ny = int(y) + 2 * dy[k];
        double ln = std::log2(4294967296.0);  // the background is far away
        if (nx >= 0 && ny >= 0 && nx < int(w) && ny < int(h) && depth[size_t(ny) * w + nx] != MV_SPLAT_EMPTY)
          ln = std::log2(double(depth[size_t(ny) * w + nx]) + 1);
        obscured += std::max(0.0, ld - ln);
      }
      const double shade = std::exp(-3.0 * obscured);
      const uint8_t* c = &frame.colours[size_t{index[at]} * 3];
      for (int k = 0; k < 3; ++k) px[k] = static_cast<uint8_t>(c[k] * shade + 0.5);
    }
  if (covered) *covered = count;
  return img;
}

}  // namespace mv::points

// Camera, light and ambient-occlusion setup, view presets and shading (see frame.h).
#include "render/frame.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "megavox/error.h"

namespace mv {

namespace {

using Vec = std::array<double, 3>;
Vec sub(Vec a, Vec b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec add(Vec a, Vec b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec mul(Vec a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(Vec a, Vec b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(Vec a, Vec b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
Vec normalize(Vec a) { return mul(a, 1.0 / std::sqrt(dot(a, a))); }
Vec vec(const double* p) { return {p[0], p[1], p[2]}; }

constexpr uint32_t kAoTable = 256;

}  // namespace

Shading parse_shading(const std::string& name) {
  for (Shading s : {Shading::shaded, Shading::normal, Shading::depth, Shading::level, Shading::heat, Shading::colour})
    if (shading_name(s) == name) return s;
  throw Error("unknown shading '" + name + "' (choose shaded, normal, depth, level, heat or colour)");
}

std::string shading_name(Shading s) {
  switch (s) {
    case Shading::shaded: return "shaded";
    case Shading::normal: return "normal";
    case Shading::depth: return "depth";
    case Shading::level: return "level";
    case Shading::heat: return "heat";
    case Shading::colour: return "colour";
  }
  return "?";
}

Camera view_camera(const Bounds& b, const std::string& view, double fov) {
  if (b.empty()) throw Error("cannot frame an empty model");
  Vec lo = vec(b.lo), hi = vec(b.hi);
  Vec c = mul(add(lo, hi), 0.5);
  double radius = std::max(0.5 * std::sqrt(dot(sub(hi, lo), sub(hi, lo))), 1e-9);
  Vec dir, up = {0, 1, 0};
  if (view == "front") dir = {0, 0, 1};
  else if (view == "back") dir = {0, 0, -1};
  else if (view == "left") dir = {-1, 0, 0};
  else if (view == "right") dir = {1, 0, 0};
  else if (view == "top") dir = {0, 1, 0}, up = {0, 0, -1};
  else if (view == "iso") dir = normalize(Vec{1, 1, 1});
  else
    throw CodedError(ErrorCode::invalid_argument,
                     "unknown view '" + view + "' (choose front, back, left, right, top or iso)",
                     setting_view);
  // The bounding sphere fits the vertical field of view, with a small margin.
  double dist = 1.05 * radius / std::sin(0.5 * fov * std::numbers::pi / 180);
  Camera cam;
  Vec eye = add(c, mul(dir, dist));
  for (int a = 0; a < 3; ++a) {
    cam.eye[a] = eye[a];
    cam.target[a] = c[a];
    cam.up[a] = up[a];
  }
  cam.fov = fov;
  return cam;
}

FrameSetup frame_setup(const GridTransform& grid, uint32_t levels, const Camera& camera, const RenderOptions& o) {
  if (o.width == 0 || o.height == 0 || o.width > 16384 || o.height > 16384)
    throw Error("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                " is outside 1..16384 pixels per side");
  if (!(camera.fov > 0 && camera.fov < 180))
    throw CodedError(ErrorCode::invalid_argument, "the field of view must lie between 0 and 180 degrees",
                     setting_fov);
  if (!(o.lod_pixels >= 0))

      throw CodedError(ErrorCode::invalid_argument, "the level-of-detail pixel size must be 0 or more",
                       setting_lod_pixels);
  if (!(o.ao_radius >= 0) || !std::isfinite(o.ao_radius))
    throw CodedError(ErrorCode::invalid_argument,
                     "the ambient-occlusion radius must be a finite number of model units, 0 or more (0: 1/20 of the grid)",
                     setting_ao_radius);
  if (o.ao_samples > kAoTable) throw Error("at most " + std::to_string(kAoTable) + " ambient-occlusion samples");
  Vec eye = vec(camera.eye), target = vec(camera.target), up = vec(camera.up);
  Vec view = sub(target, eye);
  if (!(dot(view, view) > 0))
    throw CodedError(ErrorCode::invalid_argument, "the camera's eye and target coincide",
                     setting_eye | setting_target);
  Vec fwd = normalize(view);
  Vec right = cross(fwd, up);
  if (!(dot(right, right) > 1e-20))
    throw CodedError(ErrorCode::invalid_argument, "the camera's up vector is parallel to its view direction",
                     setting_up);
  right = normalize(right);
  Vec upv = cross(right, fwd);

  FrameSetup s;
  s.width = o.width;
  s.height = o.height;
  s.levels = levels;
  // World to the root cube: one translation and one scale, so directions keep their meaning and t is the
  // depth along the view axis in root-cube units (fwd has unit length).
  const double side = grid.voxel_size * grid.resolution;
  const double tan_h = std::tan(0.5 * camera.fov * std::numbers::pi / 180);
  const double aspect = double(o.width) / o.height;
  Vec du = mul(right, 2 * tan_h * aspect / o.width);
  Vec dv = mul(upv, -2 * tan_h / o.height);
  Vec base = add(fwd, add(mul(right, tan_h * aspect * (1.0 / o.width - 1)), mul(upv, tan_h * (1 - 1.0 / o.height))));
  for (int a = 0; a < 3; ++a) {
    s.camera[MV_CAMERA_EYE + a] = static_cast<float>((eye[a] - grid.origin[a]) / side);
    s.camera[MV_CAMERA_BASE + a] = static_cast<float>(base[a]);
    s.camera[MV_CAMERA_DU + a] = static_cast<float>(du[a]);
    s.camera[MV_CAMERA_DV + a] = static_cast<float>(dv[a]);
  }
  s.camera[MV_CAMERA_TMAX] = 1e30f;
  s.proj = o.lod_pixels > 0 ? static_cast<float>(o.height / (2 * tan_h * o.lod_pixels)) : 0.0f;

  // Light from over the viewer's left shoulder.
  Vec light = normalize(add(add(mul(fwd, -0.55), mul(upv, 0.7)), mul(right, -0.45)));
  s.shadow.kind = MV_SECONDARY_SHADOW;
  s.shadow.lx = static_cast<float>(light[0]);
  s.shadow.ly = static_cast<float>(light[1]);
  s.shadow.lz = static_cast<float>(light[2]);
  s.shadow.tmax = 4.0f;  // beyond the root cube's diagonal
  s.shadow.lead = 2.0f;
  s.shadow.width = o.width;

  s.ao_samples = o.ao_samples;
  s.ao_table.resize(3 * kAoTable);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (uint32_t i = 0; i < kAoTable; ++i) {  // cosine-weighted: uniform on the disc, lifted to the hemisphere
    double r = std::sqrt((i + 0.5) / kAoTable), phi = i * golden;
    s.ao_table[3 * i] = static_cast<float>(r * std::cos(phi));
    s.ao_table[3 * i + 1] = static_cast<float>(r * std::sin(phi));
    s.ao_table[3 * i + 2] = static_cast<float>(std::sqrt(std::max(0.0, 1 - r * r)));
  }
  s.ao.kind = MV_SECONDARY_AO;
  s.ao.stride = o.ao_samples ? kAoTable / o.ao_samples : 1;
  s.ao.mask = kAoTable - 1;
  s.ao.tmax = static_cast<float>(o.ao_radius > 0 ? o.ao_radius / side : 0.05);
  s.ao.width = o.width;
  s.ao.lead = 1.0f;
  return s;
}

namespace {

struct Rgb {
  double r, g, b;
};

Rgb mix(Rgb a, Rgb b, double t) { return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t}; }

// A perceptual-ish ramp for heat maps: dark blue, purple, red, orange, pale yellow.
Rgb heat_ramp(double v) {
  static const Rgb stops[] = {{0.05, 0.03, 0.25}, {0.45, 0.10, 0.55}, {0.85, 0.20, 0.30}, {0.98, 0.60, 0.10}, {1.0, 0.97, 0.70}};
  v = std::clamp(v, 0.0, 1.0) * 4;
  int i = std::min(int(v), 3);
  return mix(stops[i], stops[i + 1], v - i);
}

// Surface normals from the depth buffer (the thesis's deferred pass, notes 1.11): per axis of the image the
// position difference toward the neighbour `reach` pixels away whose depth is closer (so silhouettes do not
// bend the normal), crossed; facing the camera. Voxel faces alone give every pixel one of six normals, which
// at a voxel per pixel reads as noise. Falls back to the face normal where no neighbour is usable.
bool depth_normal(const FrameSetup& s, const FrameResults& res, uint32_t x, uint32_t y, double n[3]) {
  const int reach = 2;
  auto point = [&](int px, int py, Vec& p, float& t) {
    if (px < 0 || py < 0 || px >= int(s.width) || py >= int(s.height)) return false;
    const MvHit h = mv_load_hit(res.hits.data(), uint32_t(py) * s.width + uint32_t(px));
    if (MV_INFO_STATUS(h.info) != MV_TRACE_HIT) return false;
    t = h.t;
    for (int a = 0; a < 3; ++a)
      p[a] = s.camera[MV_CAMERA_EYE + a] +
             t * (s.camera[MV_CAMERA_BASE + a] + px * s.camera[MV_CAMERA_DU + a] + py * s.camera[MV_CAMERA_DV + a]);
    return true;
  };
  Vec c{};
  float tc = 0;
  if (!point(int(x), int(y), c, tc)) return false;
  Vec axes[2];
  for (int k = 0; k < 2; ++k) {
    Vec lo{}, hi{};
    float tl = 0, th = 0;
    bool has_lo = k ? point(int(x), int(y) - reach, lo, tl) : point(int(x) - reach, int(y), lo, tl);
    bool has_hi = k ? point(int(x), int(y) + reach, hi, th) : point(int(x) + reach, int(y), hi, th);
    const float limit = 0.02f * tc;  // farther than this along the view axis: another surface
    has_lo = has_lo && std::abs(tl - tc) < limit;
    has_hi = has_hi && std::abs(th - tc) < limit;
    if (!has_lo && !has_hi) return false;
    axes[k] = has_hi && (!has_lo || std::abs(th - tc) <= std::abs(tl - tc)) ? sub(hi, c) : sub(c, lo);
  }
  Vec nn = cross(axes[1], axes[0]);
  double len = std::sqrt(dot(nn, nn));
  if (!(len > 0)) return false;
  Vec view;
  for (int a = 0; a < 3; ++a)
    view[a] = s.camera[MV_CAMERA_BASE + a] + x * s.camera[MV_CAMERA_DU + a] + y * s.camera[MV_CAMERA_DV + a];
  if (dot(nn, view) > 0) len = -len;
  for (int a = 0; a < 3; ++a) n[a] = nn[a] / len;
  return true;
}

// A hit's colour word as 0..1 channels (sRGB as stored).
Rgb unpack_colour(uint32_t c) { return {(c & 0xff) / 255.0, (c >> 8 & 0xff) / 255.0, (c >> 16 & 0xff) / 255.0}; }

uint8_t to_byte(double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); }

}  // namespace

bool frame_uses_colours(const RenderOptions& o) {
  return o.colours && (o.shading == Shading::shaded || o.shading == Shading::colour);
}

BeamSetup beam_setup(const FrameSetup& s, uint32_t max_cells) {
  const float* c = s.camera;
  double step = 0, depth = 0, fwd2 = 0;  // step: a pixel's stray per unit t, on the worst axis
  for (int a = 0; a < 3; ++a) {
    step = std::max<double>(step, std::abs(c[MV_CAMERA_DU + a]) + std::abs(c[MV_CAMERA_DV + a]));
    const double fwd =
        c[MV_CAMERA_BASE + a] + 0.5 * (s.width - 1.0) * c[MV_CAMERA_DU + a] + 0.5 * (s.height - 1.0) * c[MV_CAMERA_DV + a];
    depth += (0.5 - c[MV_CAMERA_EYE + a]) * fwd;
    fwd2 += fwd * fwd;
  }
  depth = std::max(depth / fwd2, 1e-3);
  // tiles of `tile` pixels: their farthest ray (tile - 1) / 2 pixels from the centre; the proof holds while
  // t * reach <= S / 2 = 1 / (2 cells), so the finest grid that keeps it to the cube's centre
  auto level = [&](uint32_t tile, float& reach) {
    reach = static_cast<float>((tile - 1) / 2.0 * step * 1.01 + 1e-9);  // above the rays' float rounding
    const double most = 1 / (2 * reach * depth);
    uint32_t cells = std::min<uint32_t>(max_cells, s.levels >= 31 ? max_cells : uint32_t{1} << s.levels);
    while (cells >= 4 && cells > most) cells /= 2;
    return cells >= 4 ? cells : 0u;
  };
  BeamSetup b;
  b.cells = level(MV_BEAM_TILE, b.reach);
  b.parent_cells = b.cells ? level(2 * MV_BEAM_TILE, b.parent_reach) : 0;
  return b;
}

Image shade(const FrameSetup& s, const RenderOptions& o, const FrameResults& res) {
  Image img;
  img.width = s.width;
  img.height = s.height;
  const size_t n = size_t{s.width} * s.height;
  img.rgb.resize(3 * n);
  const double light[3] = {s.shadow.lx, s.shadow.ly, s.shadow.lz};
  // Depth range and step range over the image, for the depth and heat ramps.
  float near = INFINITY, far = 0;
  uint32_t max_steps = 1;
  for (size_t i = 0; i < n; ++i) {
    const MvHit h = mv_load_hit(res.hits.data(), uint32_t(i));
    max_steps = std::max(max_steps, h.steps);
    if (MV_INFO_STATUS(h.info) != MV_TRACE_HIT) continue;
    near = std::min(near, h.t);
    far = std::max(far, h.t);
  }
  static const Rgb palette[] = {{0.90, 0.90, 0.90}, {0.95, 0.55, 0.25}, {0.30, 0.70, 0.35}, {0.30, 0.50, 0.90},
                                {0.85, 0.30, 0.60}, {0.95, 0.85, 0.30}, {0.35, 0.80, 0.85}, {0.60, 0.40, 0.25}};
  for (size_t i = 0; i < n; ++i) {
    const MvHit h = mv_load_hit(res.hits.data(), uint32_t(i));
    const uint32_t info = h.info;
    const double row = double(i / s.width) / std::max<uint32_t>(s.height - 1, 1);
    Rgb c = mix({0.93, 0.95, 0.98}, {0.72, 0.76, 0.83}, row);  // background
    const bool hit = MV_INFO_STATUS(info) == MV_TRACE_HIT;
    const uint32_t axis = MV_INFO_AXIS(info);
    double normal[3] = {0, 0, 0};
    if (hit && axis != MV_AXIS_NONE) normal[axis] = MV_INFO_NEGATIVE(info) ? -1 : 1;
    const double facing = axis == MV_AXIS_NONE ? 1.0 : std::max(0.0, normal[0] * light[0] + normal[1] * light[1] + normal[2] * light[2]);
    switch (o.shading) {
      case Shading::shaded:
        if (hit) {
          double smooth[3];
          double diffuse = facing;
          if (depth_normal(s, res, uint32_t(i % s.width), uint32_t(i / s.width), smooth))
            diffuse = std::max(0.0, smooth[0] * light[0] + smooth[1] * light[1] + smooth[2] * light[2]);
          double lit = res.shadow.empty() || res.shadow[i] == 0 ? 1.0 : 0.0;
          double ao = s.ao_samples && !res.ao.empty() ? 1.0 - double(res.ao[i]) / s.ao_samples : 1.0;
          double v = 0.32 * ao + 0.68 * diffuse * lit;
          // the albedo in linear light (display gamma ~2: a stored colour squared), lit, back to display
          Rgb albedo = {0.86, 0.83, 0.78};
          if (!res.colours.empty()) {
            const Rgb k = unpack_colour(res.colours[i]);
            albedo = {k.r * k.r, k.g * k.g, k.b * k.b};
          }
          c = {albedo.r * v, albedo.g * v, albedo.b * v};
          c = {std::sqrt(c.r), std::sqrt(c.g), std::sqrt(c.b)};
        }
        break;
      case Shading::normal:
        if (hit) c = {0.5 + 0.5 * normal[0], 0.5 + 0.5 * normal[1], 0.5 + 0.5 * normal[2]};
        break;
      case Shading::depth:
        if (hit) {
          double v = far > near ? (h.t - near) / (far - near) : 0.0;
          c = {1 - 0.85 * v, 1 - 0.85 * v, 1 - 0.85 * v};
        }
        break;
      case Shading::level:
        if (hit) {
          Rgb p = palette[MV_INFO_LEVEL(info) % 8];
          double v = 0.55 + 0.45 * facing;
          c = {p.r * v, p.g * v, p.b * v};
        }
        break;
      case Shading::colour:
        if (hit) c = res.colours.empty() ? Rgb{0.6, 0.6, 0.6} : unpack_colour(res.colours[i]);
        break;
      case Shading::heat:
        c = heat_ramp(std::log2(double(std::max<uint32_t>(h.steps, 1))) / std::log2(double(std::max<uint32_t>(max_steps, 2))));
        break;
    }
    img.rgb[3 * i] = to_byte(c.r);
    img.rgb[3 * i + 1] = to_byte(c.g);
    img.rgb[3 * i + 2] = to_byte(c.b);
  }
  return img;
}

}  // namespace mv

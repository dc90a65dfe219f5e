// The local-to-EPSG:4978 transform of a georeferenced cloud (see crs_frame.h). PROJ gives the exact transform of
// single points; the frame is its first-order expansion at the centre: the translation is the centre's exact
// position, the linear part PROJ's Jacobian there, taken by central differences over +-100 m (the projection's
// third derivatives leave about 1e-10 of relative error; PROJ's own rounding, below a millimetre, is divided by
// the 200 m).
// Using PROJ's own Jacobian rather than a formula for the convergence and point scale keeps every projection,
// datum shift and unit PROJ knows right without a case for each.
#include "io/crs_frame.h"

#include <proj.h>
#include <proj_experimental.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "megavox/error.h"

namespace mv::io {
namespace {

// One PROJ context, with its error messages kept for ours instead of printed.
struct CrsProjContext {
  PJ_CONTEXT* ctx = nullptr;
  std::string last;  // PROJ's last error message
  CrsProjContext() {
    ctx = proj_context_create();
    if (ctx) {
      proj_log_func(ctx, this, [](void* self, int, const char* msg) {
        if (msg) static_cast<CrsProjContext*>(self)->last = msg;
      });
      proj_log_level(ctx, PJ_LOG_ERROR);
    }
  }
  ~CrsProjContext() {
    if (ctx) proj_context_destroy(ctx);
  }
  CrsProjContext(const CrsProjContext&) = delete;
  CrsProjContext& operator=(const CrsProjContext&) = delete;
  // " (PROJ: ...)" with PROJ's reason, or "" when it gave none.
  std::string why() const {
    std::string m = last;
    if (m.empty() && ctx) {
      const int e = proj_context_errno(ctx);
      if (e != 0 && proj_context_errno_string(ctx, e)) m = proj_context_errno_string(ctx, e);
    }
    return m.empty() ? "" : " (PROJ: " + m + ")";
  }
};

struct CrsPjFree {
  void operator()(PJ* p) const { proj_destroy(p); }
};
using CrsPj = std::unique_ptr<PJ, CrsPjFree>;

[[noreturn]] void crs_fail(const std::string& crs, const std::string& what) {
  std::string head = crs.substr(0, 60);
  for (char& ch : head)
    if (ch == '\n' || ch == '\r' || ch == '\t') ch = ' ';
  if (crs.size() > 60) head += "...";
  throw Error("cannot place the cloud on the globe: the CRS \"" + head + "\" " + what);
}

// The unit (metres or radians per unit) of axis `axis` of a CRS's coordinate system; 0 when PROJ cannot say.
double crs_axis_unit(PJ_CONTEXT* ctx, const PJ* crs, int axis) {
  CrsPj cs(proj_crs_get_coordinate_system(ctx, crs));
  double factor = 0;
  if (!cs || axis >= proj_cs_get_axis_count(ctx, cs.get())) return 0;
  if (!proj_cs_get_axis_info(ctx, cs.get(), axis, nullptr, nullptr, nullptr, &factor, nullptr, nullptr, nullptr))
    return 0;
  return factor;
}

int crs_axis_count(PJ_CONTEXT* ctx, const PJ* crs) {
  CrsPj cs(proj_crs_get_coordinate_system(ctx, crs));
  return cs ? proj_cs_get_axis_count(ctx, cs.get()) : 0;
}

// A BoundCRS (WKT 1 with TOWGS84) describes its source CRS's axes.
CrsPj crs_unbound(PJ_CONTEXT* ctx, const PJ* crs) {
  if (proj_get_type(crs) == PJ_TYPE_BOUND_CRS) return CrsPj(proj_get_source_crs(ctx, crs));
  return CrsPj(proj_clone(ctx, crs));
}

// A CRS opened for exact transforms of its points to EPSG:4978.
struct CrsExact {
  std::unique_ptr<CrsProjContext> pc;
  CrsPj op;                // source (x east, y north) -> EPSG:4978
  std::string crs, name;   // the CRS as given, and its name
  double unit[3] = {1, 1, 1};  // metres (or, horizontally for a geographic CRS, radians) per CRS unit
  double z_feed = 1;       // the CRS's z times this is what `op` takes (a 2D CRS's op takes metres)
  bool geographic = false, geocentric = false;

  // p (CRS units) in EPSG:4978.
  void to_ecef(const double p[3], double out[3]) const {
    PJ_COORD c = proj_coord(p[0], p[1], p[2] * z_feed, 0);
    proj_errno_reset(op.get());
    PJ_COORD r = proj_trans(op.get(), PJ_FWD, c);
    if (!std::isfinite(r.xyz.x) || !std::isfinite(r.xyz.y) || !std::isfinite(r.xyz.z) || r.xyz.x == HUGE_VAL)
      crs_fail(crs, "cannot transform the point (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                        std::to_string(p[2]) + ") to EPSG:4978" + pc->why());
    out[0] = r.xyz.x;
    out[1] = r.xyz.y;
    out[2] = r.xyz.z;
  }

  // Keeps, of PROJ's candidate transformations (each for its own area), the one it uses at `p`: every point of
  // the frame then goes through the same one.
  void lock_at(const double p[3]) {
    double unused[3];
    to_ecef(p, unused);
    if (PJ* used = proj_trans_get_last_used_operation(op.get())) op.reset(used);
  }
};

CrsExact crs_open(const std::string& crs) {
  CrsExact e;
  e.crs = crs;
  e.pc = std::make_unique<CrsProjContext>();
  PJ_CONTEXT* ctx = e.pc->ctx;
  if (!ctx) crs_fail(crs, "cannot be read: PROJ cannot start (out of memory)");
  if (crs.empty()) crs_fail(crs, "is empty: the cloud has no CRS");
  if (!proj_context_get_database_path(ctx))
    crs_fail(crs, "cannot be read: PROJ cannot open its database proj.db (install proj-data, or set PROJ_DATA to "
                  "the folder that holds proj.db)" + e.pc->why());
  CrsPj src(proj_create(ctx, crs.c_str()));
  if (!src) crs_fail(crs, "cannot be read as OGC WKT or an EPSG code" + e.pc->why());
  if (!proj_is_crs(src.get())) crs_fail(crs, "is not a coordinate reference system");
  if (const char* n = proj_get_name(src.get())) e.name = n;

  // The horizontal part and the vertical one, if separate.
  CrsPj base = crs_unbound(ctx, src.get()), horizontal, vertical;
  if (proj_get_type(base.get()) == PJ_TYPE_COMPOUND_CRS) {
    CrsPj h(proj_crs_get_sub_crs(ctx, base.get(), 0)), v(proj_crs_get_sub_crs(ctx, base.get(), 1));
    if (!h || !v) crs_fail(crs, "is a compound CRS whose parts PROJ cannot read" + e.pc->why());
    horizontal = crs_unbound(ctx, h.get());
    vertical = crs_unbound(ctx, v.get());
    if (proj_get_type(vertical.get()) != PJ_TYPE_VERTICAL_CRS)
      crs_fail(crs, "is a compound CRS whose second part is not a vertical CRS");
  } else {
    horizontal = std::move(base);
  }
  const PJ_TYPE type = proj_get_type(horizontal.get());
  switch (type) {
    case PJ_TYPE_PROJECTED_CRS: break;
    case PJ_TYPE_GEOGRAPHIC_2D_CRS:
    case PJ_TYPE_GEOGRAPHIC_3D_CRS: e.geographic = true; break;
    case PJ_TYPE_GEOCENTRIC_CRS: e.geocentric = !vertical; break;
    default: break;
  }
  if (type != PJ_TYPE_PROJECTED_CRS && !e.geographic && !e.geocentric)
    crs_fail(crs, "has no known link to the Earth's centre (it is not a projected, geographic or geocentric CRS, "
                  "nor one of those with a vertical CRS)");
  const int axes = crs_axis_count(ctx, horizontal.get());
  e.unit[0] = crs_axis_unit(ctx, horizontal.get(), 0);
  e.unit[1] = crs_axis_unit(ctx, horizontal.get(), 1);
  if (vertical) {
    e.unit[2] = crs_axis_unit(ctx, vertical.get(), 0);
  } else if (axes >= 3) {
    e.unit[2] = crs_axis_unit(ctx, horizontal.get(), 2);
  } else {
    // A 2D CRS: heights in the horizontal unit for a projected CRS (the LAS practice), metres for a geographic
    // one. PROJ's transform of a 2D CRS takes z as ellipsoidal metres, so z is fed in metres.
    e.unit[2] = e.geographic ? 1.0 : e.unit[0];
    e.z_feed = e.unit[2];
  }
  if (!(e.unit[0] > 0) || !(e.unit[1] > 0) || !(e.unit[2] > 0))
    crs_fail(crs, "has an axis whose unit PROJ cannot say" + e.pc->why());

  // A 2D source is promoted to 3D (ellipsoidal height in metres) so that PROJ keeps the height; where it cannot
  // be, the 2D transform also passes z through as metres.
  CrsPj from(axes < 3 && !vertical ? proj_crs_promote_to_3D(ctx, nullptr, src.get()) : nullptr);
  CrsPj ecef(proj_create(ctx, "EPSG:4978"));
  if (!ecef) crs_fail(crs, "cannot be placed: PROJ does not know EPSG:4978" + e.pc->why());
  CrsPj op(proj_create_crs_to_crs_from_pj(ctx, from ? from.get() : src.get(), ecef.get(), nullptr, nullptr));
  if (!op) crs_fail(crs, "has no transformation to EPSG:4978 that PROJ knows" + e.pc->why());
  // x east (or longitude), y north (or latitude), as a LAS file stores them, whatever the CRS's axis order.
  e.op.reset(proj_normalize_for_visualization(ctx, op.get()));
  if (!e.op) crs_fail(crs, "cannot be put in easting, northing order" + e.pc->why());
  return e;
}

// Geodetic latitude and longitude (radians) of an EPSG:4978 point on WGS 84 (Bowring's iteration; converges to
// 1e-12 rad in three steps anywhere off the Earth's centre).
void crs_geodetic(const double p[3], double& lat, double& lon) {
  const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  lon = std::atan2(p[1], p[0]);
  const double r = std::hypot(p[0], p[1]);
  lat = std::atan2(p[2], r * (1 - e2));
  for (int i = 0; i < 5; ++i) {
    const double s = std::sin(lat), n = a / std::sqrt(1 - e2 * s * s);
    lat = std::atan2(p[2] + e2 * n * s, r);
  }
}

double crs_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The frame of `e` at `centre`; `up` receives the ellipsoid's normal there.
CrsFrame crs_build(const CrsExact& e, const double centre[3], double up[3]) {
  CrsFrame f{};
  f.crs_name = e.name;
  e.to_ecef(centre, f.origin_ecef);
  double lat, lon;
  crs_geodetic(f.origin_ecef, lat, lon);
  const double east[3] = {-std::sin(lon), std::cos(lon), 0};
  const double north[3] = {-std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat)};
  up[0] = std::cos(lat) * std::cos(lon);
  up[1] = std::cos(lat) * std::sin(lon);
  up[2] = std::sin(lat);

  const double step_metres = 100;
  for (int i = 0; i < 3; ++i) {
    // The step in CRS units: 100 m, for degrees by the Earth's radius.
    const double unit_m = e.geographic && i < 2 ? e.unit[i] * 6378137.0 : e.unit[i];
    const double h = step_metres / unit_m;
    double lo[3] = {centre[0], centre[1], centre[2]}, hi[3] = {centre[0], centre[1], centre[2]};
    lo[i] -= h;
    hi[i] += h;
    double a[3], b[3], col[3];
    e.to_ecef(lo, a);
    e.to_ecef(hi, b);
    for (int k = 0; k < 3; ++k) col[k] = (b[k] - a[k]) / (2 * h);  // ECEF metres per CRS unit
    double metres = e.unit[i];
    if (e.geographic && i < 2) {
      // Metres per degree along the axis at the centre.
      metres = std::sqrt(crs_dot(col, col));
      if (!(metres > 1e-3)) crs_fail(e.crs, "cannot be placed at a pole: longitude has no east there");
    }
    f.units_to_metres[i] = metres;
    for (int k = 0; k < 3; ++k) f.transform[4 * i + k] = col[k] / metres;
    f.transform[4 * i + 3] = 0;
  }
  for (int k = 0; k < 3; ++k) f.transform[12 + k] = f.origin_ecef[k];
  f.transform[15] = 1;

  const double* gx = &f.transform[0];
  const double* gy = &f.transform[4];
  if (e.geocentric) {
    f.convergence_degrees = 0;
    f.scale = 1;
  } else {
    f.convergence_degrees = std::atan2(crs_dot(gy, east), crs_dot(gy, north)) * 180 / std::numbers::pi;
    f.scale = 2 / (std::sqrt(crs_dot(gx, gx)) + std::sqrt(crs_dot(gy, gy)));
  }
  return f;
}

}  // namespace

void check_crs(const std::string& crs) { (void)crs_open(crs); }

CrsFrame crs_frame(const std::string& crs, const double centre[3]) {
  CrsExact e = crs_open(crs);
  e.lock_at(centre);
  double up[3];
  return crs_build(e, centre, up);
}

double crs_frame_error_metres(const std::string& crs, const double centre[3], const double half_extent[3],
                              double* vertical_metres) {
  CrsExact e = crs_open(crs);
  e.lock_at(centre);
  double up[3];
  const CrsFrame f = crs_build(e, centre, up);
  double worst_h = 0, worst_v = 0;
  // Corners (no zero in a) and edge midpoints (one zero) of the box.
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy)
      for (int iz = -1; iz <= 1; ++iz) {
        const int a[3] = {ix, iy, iz};
        if ((ix == 0) + (iy == 0) + (iz == 0) > 1) continue;
        double p[3], local[3], exact[3], d[3];
        for (int k = 0; k < 3; ++k) {
          p[k] = centre[k] + a[k] * half_extent[k];
          local[k] = (p[k] - centre[k]) * f.units_to_metres[k];
        }
        e.to_ecef(p, exact);
        for (int k = 0; k < 3; ++k)
          d[k] = exact[k] - (f.transform[12 + k] + f.transform[k] * local[0] + f.transform[4 + k] * local[1] +
                             f.transform[8 + k] * local[2]);
        const double v = crs_dot(d, up);
        worst_h = std::max(worst_h, std::sqrt(std::max(0.0, crs_dot(d, d) - v * v)));
        worst_v = std::max(worst_v, std::fabs(v));
      }
  if (vertical_metres) *vertical_metres = worst_v;
  return worst_h;
}

}  // namespace mv::io

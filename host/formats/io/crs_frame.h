// Placing a georeferenced point cloud on the globe: one rigid (plus scale) transform from a tileset's local
// frame to Earth-centred coordinates (EPSG:4978, metres), as a 3D Tiles root `transform` needs, computed with
// PROJ from the cloud's own CRS (OGC WKT 1 or 2, "EPSG:N" or "EPSG:N+M").
//
// The local frame. A point p given in the CRS's own units (x, y, z exactly as stored in the file) has the local
// position
//     p_local[i] = (p[i] - centre[i]) * units_to_metres[i]        (i = 0, 1, 2)
// that is metres along the CRS's own axes (easting, northing, up; for a geographic CRS longitude, latitude,
// height) about the centre. transform * p_local is that point in EPSG:4978. The transform's linear part is
// PROJ's own Jacobian at the centre (exact differences of its transform to EPSG:4978): for the usual conformal
// projections (UTM, Lambert, transverse Mercator, the state planes) it is the rotation from grid axes into true
// east, north, up at the centre's geodetic position, by the grid convergence, times 1/k for the point scale k
// (with the height above the ellipsoid), so the writer needs no rotation of its own.
//
// Units. Horizontal: the CRS's axis unit (a foot is 0.3048 m, a US survey foot 1200/3937 m); for a geographic
// CRS the metres per degree of longitude and of latitude at the centre. Vertical: the vertical CRS's unit for a
// compound CRS, the third axis's for a 3D CRS, and for a 2D projected CRS the horizontal unit (the LAS practice,
// which Cesium ion and Esri follow: a cloud in feet has its heights in feet; PROJ and PDAL would take them as
// metres). Heights without a vertical CRS are taken as ellipsoidal (no geoid model is applied).
//
// Errors (mv::Error, naming the CRS's first 60 characters): an unparseable or unknown CRS, one with no known
// link to EPSG:4978 (an engineering or vertical-only CRS), a centre PROJ cannot transform, PROJ without its
// database (proj.db, in Debian's proj-data). Each call has its own PROJ context: calls may run on any threads.
#pragma once
#include <string>

namespace mv::io {

struct CrsFrame {
  double transform[16];        // column-major 4x4: local (metres, CRS axes, about the centre) -> EPSG:4978
  double origin_ecef[3];       // the centre in EPSG:4978 (the transform's translation)
  double units_to_metres[3];   // metres per CRS unit along x, y, z (see the file comment)
  std::string crs_name;        // the CRS's name as PROJ reads it ("NAD83(HARN) / Oregon GIC Lambert (ft)")
  double convergence_degrees;  // angle from true north to grid north at the centre, positive eastwards
  double scale;                // grid metres per true metre at the centre's height: k / (1 + h / R)
};

// The frame of a cloud in `crs` about `centre` (x, y, z in the CRS's own units, as stored in the file).
CrsFrame crs_frame(const std::string& crs, const double centre[3]);

// Throws the mv::Error crs_frame would for a CRS that cannot be placed at all (unknown, unparseable, not linked
// to the Earth), without a point: how a command refuses a wrong --crs before any work.
void check_crs(const std::string& crs);

// The largest horizontal distance (metres), over the corners and edge midpoints of the box centre ± half_extent
// (CRS units), between PROJ's exact transform of a point to EPSG:4978 and crs_frame's transform of it:
// what one rigid transform costs over that extent. Horizontal is perpendicular to the up direction at the
// centre; `vertical_metres`, when given, receives the largest distance along it (the Earth's curvature, about
// d^2 / 12.7e6 m at d metres from the centre, is most of it).
double crs_frame_error_metres(const std::string& crs, const double centre[3], const double half_extent[3],
                              double* vertical_metres = nullptr);

}  // namespace mv::io

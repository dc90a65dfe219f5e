// Where a 3D Tiles 1.1 tileset sits: the local frame its tiles and bounding volumes use, and the root transform
// that takes that frame to the globe (EPSG:4978, through io/crs_frame.h) or, for a cloud without a usable CRS,
// back to the input's own coordinates.
//
// The local frame is crs_frame's: p_local = (p - origin) * units_to_metres per axis, axes as the CRS's, where p
// is a point in the input's coordinates (offset + scale * xyz) and origin the centre of the points' bounds.
// Without a CRS units_to_metres is 1 (the input's units) and the root transform a translation by origin.
#pragma once
#include <string>

#include "megavox/points.h"

namespace mv::io {

struct TilePlacement {
  std::string crs;             // the CRS placed with ("EPSG:N", WKT, ...), or empty: local
  std::string crs_name;        // its name as PROJ reads it, or empty
  std::string declared;        // the CRS the input declared (PointCloudInfo::crs), or empty
  std::string note;            // why a declared CRS was not used, or empty
  double lo[3] = {}, hi[3] = {};  // the points' bounds, in the input's coordinates
  double origin[3] = {};       // the local frame's origin: the bounds' centre
  double units_to_metres[3] = {1, 1, 1};
  double transform[16] = {};   // column-major: local -> EPSG:4978 (placed) or the input's coordinates
  double error_metres = 0;     // crs_frame_error_metres over the bounds (0 when local)
  double vertical_error_metres = 0;
  bool placed() const { return !crs.empty(); }
};

// The CRS text PROJ can take for a declared one: "GeoTIFF keys (EPSG:N)" (the LAS reader's summary of a
// GeoKeyDirectory) -> "EPSG:N"; other GeoTIFF summaries (no code, user-defined) -> empty; anything else as it is.
std::string tiles3d_usable_crs(const std::string& declared);

// The placement of `h`: with `crs` (non-empty: the user's choice, over the declared one) it must work, else
// mv::Error names it and says why; a declared CRS PROJ cannot place leaves the tileset local, saying why in
// `note`. Throws mv::Error when the hierarchy holds no points.
TilePlacement tiles3d_place(const PointHierarchy& h, const std::string& crs);
// The same from the cloud's grid bounds (its points' min and max per axis), for a part of the hierarchy.
TilePlacement tiles3d_place(const PointCloudInfo& source, const int64_t lo[3], const int64_t hi[3], const std::string& crs);

}  // namespace mv::io

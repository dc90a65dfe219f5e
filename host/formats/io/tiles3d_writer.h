// Point-cloud LOD hierarchies as 3D Tiles: DIR/tileset.json and one tile per node that holds points, 3D Tiles 1.1
// (DIR/tiles/NAME.glb, placed on the globe when the cloud has a CRS) or 1.0 (DIR/tiles/NAME.pnts).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "megavox/points.h"

namespace mv::io {

struct Tiles3dOptions {
  int minor_version = 1;  // 1: 3D Tiles 1.1, glb content; 0: 3D Tiles 1.0, .pnts content
  std::string crs;        // the CRS to place with ("EPSG:N", WKT), over the input's; empty: the input's
  bool meshopt = true;    // 1.1: every glb buffer view compressed with EXT_meshopt_compression
};

// Writes the tileset for `h` into DIR (replacing an earlier tileset there; see write_dir_atomically).
// Both versions:
//   - Tiles nest as the nodes do, refine REPLACE: a leaf holds all of its points, an inner node its
//     representatives, so the leaves' point counts add up to h.points_kept. Tile names are the node's octant
//     path ("r", "r3", "r37", ...); children's boxes are their node cubes; geometric errors as tiles3d_layout.h
//     says, in the tileset's units.
//   - RGB (with kPointRgb): the stored values where none of the cloud's exceeds 255, else value >> 8 (16-bit
//     colour, as LAS stores it).
//   - Per-point properties (intensity, normals, the attribute record's fields) as tiles3d_properties.h says;
//     asset.extras lists them ("properties") and those skipped with the reason ("skippedProperties").
// 1.1 (the default):
//   - Content: io/glb_points.h (KHR_mesh_quantization positions, COLOR_0, EXT_structural_metadata property
//     attributes, "classification" as EXT_mesh_features feature IDs, EXT_meshopt_compression).
//   - Coordinates: the local frame of tiles3d_place.h, about the centre of the points' bounds. The root's
//     `transform` takes it to EPSG:4978 when the cloud has a CRS PROJ can place (options.crs, else the input's
//     own; "GeoTIFF keys (EPSG:N)" is EPSG:N), else back to the input's coordinates. Units: metres when placed,
//     else the input's. The root's box is the points' bounds, not its cube.
//   - asset.extras: "crs" (the CRS placed with, or null), "declaredCrs", "placement" ("EPSG:4978" or
//     "local"), "placementNote" (why a declared CRS was not used), "placementErrorMetres" and
//     "placementVerticalErrorMetres" (crs_frame_error_metres over the bounds), "localOrigin" (the frame's
//     origin in the input's coordinates), "unitsToMetres", "upAxis" ("Z" when placed, else the input's).
// 1.0:
//   - Coordinates are the input's own (world = offset + scale * xyz): RTC_CENTER is the node's cube centre
//     (double), POSITION float32 relative to it; every box is the node's cube. Properties go in each tile's
//     batch table. asset.extras: "crs" (options.crs, else the input's declared CRS, or null), "upAxis".
// Throws mv::Error naming DIR on any failure, leaving DIR as it was; options.crs that PROJ cannot place is an
// error before anything is written.
void write_3dtiles(const std::string& dir, const PointHierarchy& h, const Tiles3dOptions& options = {});

// A tileset written by several processes (a point build over MPI ranks, the same bytes): the process with the
// whole hierarchy's nodes calls `start` with the temporary folder and the colour shift once everything that can
// refuse the input has passed, writes the tiles of the nodes `elsewhere` does not mark while the others write
// theirs (write_3dtiles_part), then calls `finish`, which returns once they are done (it throws when one failed:
// the folder goes), and writes tileset.json. h holds the points of its own nodes alone, so the points' bounds
// and colour depth (the colour shift) over every process come with the share.
struct Tiles3dShare {
  std::vector<bool> elsewhere;  // per node of h
  std::function<void(const std::string& tmp_dir, int colour_shift)> start;
  std::function<void()> finish;
  int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  // every point's grid bounds, as write_3dtiles_part gets them
  bool wide_colour = false;                       // some point's colour needs 16 bits
};
void write_3dtiles(const std::string& dir, const PointHierarchy& h, const Tiles3dOptions& options,
                   const Tiles3dShare& share);

// The tiles of every node of `part` (nodes of the whole hierarchy with their points, on its grid) into
// tmp_dir/tiles, as write_3dtiles writes them: `lo`, `hi` are the whole cloud's grid bounds (its placement),
// colour_shift the one `start` got.
void write_3dtiles_part(const std::string& tmp_dir, const PointHierarchy& part, const Tiles3dOptions& options,
                        const int64_t lo[3], const int64_t hi[3], int colour_shift);

}  // namespace mv::io

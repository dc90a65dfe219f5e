// Point-cloud LOD hierarchies as 3D Tiles 1.0: DIR/tileset.json and one Point Cloud tile (DIR/tiles/NAME.pnts)
// per node that holds points.
#pragma once
#include <string>

#include "megavox/points.h"

namespace mv::io {

// Writes the tileset for `h` into DIR (replacing an earlier tileset there; see write_dir_atomically).
//   - Tiles nest as the nodes do, refine REPLACE: a leaf holds all of its points, an inner node its
//     representatives, so the leaves' POINTS_LENGTH add up to h.points_kept.
//   - Coordinates are the input's own (world = offset + scale * xyz, docs/points.md): RTC_CENTER is
//     the node's cube centre (double), POSITION float32 relative to it; boundingVolume.box is the node's cube.
//   - RGB (with kPointRgb): the stored values where none of the cloud's exceeds 255, else value >> 8 (16-bit
//     colour, as LAS stores it).
//   - asset.extras: "crs" (the input's declared CRS, or null) and "upAxis" ("Z" or "Y").
//   - Tile names are the node's octant path ("r", "r3", "r37", ...); geometric errors as tiles3d_layout.h says.
// Throws mv::Error naming DIR on any failure, leaving DIR as it was.
void write_3dtiles(const std::string& dir, const PointHierarchy& h);

}  // namespace mv::io

// Where each node of a point hierarchy goes in a 3D Tiles tileset: its tile's name, box and geometric error.
#pragma once
#include <string>
#include <vector>

#include "megavox/points.h"

namespace mv::io {

struct TileLayout {
  std::string name;       // the node's path from the root: "r", then one octant digit per level ("r07")
  double center[3] = {};  // the node's cube in the frame's coordinates (world: offset + scale * grid)
  double half[3] = {};    // half its side per axis (|scale| * side / 2, times the frame's factor)
  double geometric_error = 0;
};

// The coordinates boxes and errors are given in: (world - origin) * factor per axis. The default is the input's
// own world coordinates; a 3D Tiles 1.1 tileset uses its local frame (tiles3d_place.h: metres when placed).
struct TileFrame {
  double origin[3] = {0, 0, 0};
  double factor[3] = {1, 1, 1};
};

// One entry per node, in node order. Checks first that the hierarchy is what points.h promises (a tree laid
// out breadth-first, codes matching the layout, point ranges inside the columns, leaves adding up to
// points_kept) and throws mv::Error saying what is wrong otherwise.
//
// Geometric error, in the frame's units (the input's by default), is what rendering a node instead of its
// children costs:
//   a leaf: 0 (it holds all of its points);
//   an inner node: its cube's side / r, where r = sqrt(representatives) is the grid resolution its
//   representatives resolve (scans are surfaces: a surface through a cube of r^3 cells touches about r^2 of
//   them); with no representatives, the side itself. Where that is not above every child's error (a node whose
//   few representatives sit in one corner), it is twice the largest child's, so errors always fall downwards.
// `elsewhere` marks nodes whose points another process holds (Tiles3dShare): their counts are checked, not where
// their points lie in h.
std::vector<TileLayout> tiles3d_layout(const PointHierarchy& h, const TileFrame& frame = {},
                                       const std::vector<bool>& elsewhere = {});

// One node's name, centre and half side (no geometric error: that takes its subtree); the node may be of a part
// of the hierarchy (h gives the grid).
TileLayout tile_box(const PointHierarchy& h, const PointNode& n, const TileFrame& frame = {});

// The error of showing none of the tileset: the root cube's side, or twice the root's error when that is larger.
double tileset_geometric_error(const std::vector<TileLayout>& tiles);

}  // namespace mv::io

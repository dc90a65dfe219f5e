// Small point hierarchies made by hand for the 3D Tiles tests: a plain octree over clustered points (split
// where a node holds more than `capacity`, every k-th point of an inner node's subtree as its
// representatives), laid out as points.h says. Not the project's LOD builder: only its output's shape.
#pragma once
#include <cstdint>
#include <string>

#include "megavox/points.h"

namespace mv::test {

enum class Colour { none, bits8, bits16 };

struct SyntheticCloud {
  uint32_t points = 5000;
  uint32_t capacity = 200;
  uint32_t max_level = 8;
  uint32_t shift = 1;
  Colour colour = Colour::bits16;
  bool z_up = true;
  std::string crs = "EPSG:32633";
  uint64_t seed = 7;
};

PointHierarchy synthetic_hierarchy(const SyntheticCloud& c);

}  // namespace mv::test

#include "colour_reference.h"

#include <map>
#include <set>

namespace mv::ref {

namespace {

uint64_t interleave_cell(uint32_t x, uint32_t y, uint32_t z) {
  uint64_t code = 0;
  for (uint32_t b = 0; b < 21; ++b)
    code |= uint64_t(x >> b & 1) << (3 * b) | uint64_t(y >> b & 1) << (3 * b + 1) | uint64_t(z >> b & 1) << (3 * b + 2);
  return code;
}

struct Sums {
  uint64_t c[3] = {0, 0, 0};
  uint64_t count = 0;
};

uint8_t rounded_mean(uint64_t sum, uint64_t count) {
  // floor(sum / count + 1/2), exactly: the remainder decides.
  return static_cast<uint8_t>(sum / count + (2 * (sum % count) >= count ? 1 : 0));
}

struct PreorderWalk {
  std::vector<std::map<uint64_t, Sums>> levels;
  std::vector<ColourNode> out;
  void walk(uint32_t level, uint64_t code) {
    const Sums& s = levels[level].at(code);
    ColourNode n;
    n.level = level;
    n.code = code;
    for (int c = 0; c < 3; ++c) n.rgb[c] = rounded_mean(s.c[c], s.count);
    out.push_back(n);
    if (level == 0) return;
    for (uint64_t o = 0; o < 8; ++o)
      if (levels[level - 1].count(code * 8 + o)) walk(level - 1, code * 8 + o);
  }
};

}  // namespace

std::vector<uint64_t> cloud_voxel_keys(const std::vector<uint32_t>& cells) {
  std::set<uint64_t> keys;
  for (size_t p = 0; p + 2 < cells.size(); p += 3) keys.insert(interleave_cell(cells[p], cells[p + 1], cells[p + 2]));
  return {keys.begin(), keys.end()};
}

std::vector<ColourNode> preorder_colours(const std::vector<uint32_t>& cells, const std::vector<uint32_t>& rgb,
                                         uint32_t levels) {
  PreorderWalk w;
  w.levels.resize(levels + 1);
  std::map<uint64_t, Sums>& points = w.levels[0];
  for (size_t p = 0; p < rgb.size(); ++p) {
    Sums& s = points[interleave_cell(cells[3 * p], cells[3 * p + 1], cells[3 * p + 2])];
    for (int c = 0; c < 3; ++c) s.c[c] += rgb[p] >> (8 * c) & 255;
    ++s.count;
  }
  if (points.empty()) return {};
  // Voxels count once each, with their rounded colour, in every ancestor.
  for (const auto& [code, s] : points)
    for (uint32_t l = 1; l <= levels; ++l) {
      Sums& up = w.levels[l][code >> (3 * l)];
      for (int c = 0; c < 3; ++c) up.c[c] += rounded_mean(s.c[c], s.count);
      ++up.count;
    }
  w.walk(levels, 0);
  return w.out;
}

NodeColours::NodeColours(const std::vector<uint64_t>& sorted_voxels, uint32_t levels, const std::vector<uint8_t>& rgb)
    : index_(levels + 1), rgb_(rgb) {
  uint64_t next = 0;
  for (size_t k = 0; k < sorted_voxels.size(); ++k) {
    const uint64_t v = sorted_voxels[k];
    for (uint32_t l = levels; l >= 1; --l) {  // the nodes above v that no earlier voxel opened, root first
      const uint64_t code = l >= 22 ? 0 : v >> (3 * l);
      if (k == 0 || code != (l >= 22 ? 0 : sorted_voxels[k - 1] >> (3 * l))) index_[l][code] = next++;
    }
    index_[0][v] = next++;
  }
}

uint32_t NodeColours::at(uint32_t level, uint32_t x, uint32_t y, uint32_t z) const {
  uint64_t code = 0;
  for (uint32_t b = 0; b < 21; ++b)
    code |= (uint64_t{x} >> b & 1) << (3 * b) | (uint64_t{y} >> b & 1) << (3 * b + 1) | (uint64_t{z} >> b & 1) << (3 * b + 2);
  if (level >= index_.size()) return 0;
  const auto it = index_[level].find(code);
  if (it == index_[level].end() || 3 * it->second + 2 >= rgb_.size()) return 0;
  const uint8_t* c = &rgb_[3 * it->second];
  return c[0] | uint32_t{c[1]} << 8 | uint32_t{c[2]} << 16 | 0xff000000u;
}

}  // namespace mv::ref

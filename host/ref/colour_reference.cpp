#include "colour_reference.h"

#include <cmath>

#include "reference.h"

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

namespace {

struct Nearest {
  double d2;
  double wb, wc;  // the nearest point's weights of b and c
};

// The point of triangle abc nearest p, as in Ericson's Real-Time Collision Detection 5.1.5 (regions: the three
// corners, the three edges, the inside; a triangle of no area beside p goes to a or c). The dot products with
// p - b and p - c come from those with p - a and the triangle's Gram matrix (ab.ab, ab.ac, ac.ac), and the inside
// divides by that matrix's determinant, which equals Ericson's va + vb + vc.
Nearest nearest_point(const double a[3], const double b[3], const double c[3], const double p[3]) {
  double ab[3], ac[3], ap[3];
  for (int k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
  }
  const double ab_ab = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  const double ab_ac = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
  const double ac_ac = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
  const double determinant = ab_ab * ac_ac - ab_ac * ab_ac;
  const double d1 = ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2];
  const double d2 = ac[0] * ap[0] + ac[1] * ap[1] + ac[2] * ap[2];
  const double d3 = d1 - ab_ab, d4 = d2 - ab_ac;  // ab.(p - b), ac.(p - b)
  const double d5 = d1 - ab_ac, d6 = d2 - ac_ac;  // ab.(p - c), ac.(p - c)
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  double v = 0, w = 0;
  if (d1 <= 0 && d2 <= 0) {
  } else if (d3 >= 0 && d4 <= d3) {
    v = 1;
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    v = d1 / (d1 - d3);
  } else if (d6 >= 0 && d5 <= d6) {
    w = 1;
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    w = d2 / (d2 - d6);
  } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    v = 1 - t;
    w = t;
  } else if (determinant > 0) {
    const double inv = 1 / determinant;
    v = vb * inv;
    w = vc * inv;
  } else {
    w = d2 > 0 ? 1 : 0;
  }
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    const double q = a[k] + ab[k] * v + ac[k] * w, e = p[k] - q;
    d += e * e;
  }
  return {d, v, w};
}

}  // namespace

namespace {

// Channel `ch` of texture t bilinearly at (u, v): the texel centres around the point, repeating at the edges.
uint32_t bilinear(const RefTexture& t, double u, double v, int ch) {
  const double w = t.width, h = t.height;
  const double x = (u - std::floor(u)) * w - 0.5;
  const double y = (1.0 - (v - std::floor(v))) * h - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  auto at = [&](double px, double py) {
    const int64_t ix = (int64_t(px) + t.width) % t.width, iy = (int64_t(py) + t.height) % t.height;
    return double(t.rgb[size_t(iy) * t.width + size_t(ix)] >> (8 * ch) & 255);
  };
  const double c = (at(x0, y0) * (1.0 - fx) + at(x0 + 1, y0) * fx) * (1.0 - fy) +
                   (at(x0, y0 + 1) * (1.0 - fx) + at(x0 + 1, y0 + 1) * fx) * fy;
  const double r = std::floor(c + 0.5);
  return uint32_t(r <= 0 ? 0 : r >= 255 ? 255 : r);
}

}  // namespace

MeshVoxelColours mesh_voxel_colours(const std::vector<float>& grid_tris, const std::vector<uint32_t>& tri_rgb,
                                    uint32_t resolution, const std::vector<uint32_t>& tri_tex,
                                    const std::vector<float>& tri_uv, const std::vector<RefTexture>& textures) {
  struct Best {
    double d2;
    uint32_t tri;
    double wb, wc;
  };
  std::map<uint64_t, Best> best;
  for (size_t t = 0; t < grid_tris.size() / 9; ++t) {
    const std::vector<float> one(grid_tris.begin() + 9 * t, grid_tris.begin() + 9 * t + 9);
    double v[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) v[i][k] = one[3 * i + k];
    for (uint64_t key : voxelize(one, resolution)) {
      uint32_t c[3] = {0, 0, 0};
      for (int bit = 0; bit < 21; ++bit)
        for (int k = 0; k < 3; ++k) c[k] |= uint32_t(key >> (3 * bit + k) & 1) << bit;
      const double p[3] = {c[0] + 0.5, c[1] + 0.5, c[2] + 0.5};
      const Nearest q = nearest_point(v[0], v[1], v[2], p);
      auto it = best.find(key);
      if (it == best.end() || q.d2 < it->second.d2) best[key] = {q.d2, uint32_t(t), q.wb, q.wc};
    }
  }
  MeshVoxelColours out;
  for (const auto& [key, b] : best) {
    uint32_t rgb = 0;
    const uint32_t tex = tri_tex.empty() ? 0xffffffffu : tri_tex[b.tri];
    if (tex != 0xffffffffu) {
      const double wa = 1.0 - b.wb - b.wc;
      const float* uv = &tri_uv[6 * size_t{b.tri}];
      const double u = double(uv[0]) * wa + double(uv[2]) * b.wb + double(uv[4]) * b.wc;
      const double v = double(uv[1]) * wa + double(uv[3]) * b.wb + double(uv[5]) * b.wc;
      for (int ch = 0; ch < 3; ++ch) rgb |= bilinear(textures[tex], u, v, ch) << (8 * ch);
      out.keys.push_back(key);
      out.rgb.push_back(rgb);
      continue;
    }
    for (int ch = 0; ch < 3; ++ch) {
      const uint32_t tri = b.tri;  // a lambda may not capture a structured binding before C++20 in clang 14
      auto channel = [&](int k) { return double(tri_rgb[3 * tri + k] >> (8 * ch) & 255); };
      const double x = channel(0) * (1 - b.wb - b.wc) + channel(1) * b.wb + channel(2) * b.wc;
      const double r = std::floor(x + 0.5);
      rgb |= uint32_t(r <= 0 ? 0 : r >= 255 ? 255 : r) << (8 * ch);
    }
    out.keys.push_back(key);
    out.rgb.push_back(rgb);
  }
  return out;
}

}  // namespace mv::ref

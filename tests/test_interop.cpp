// SymVox-family files in and out, OpenVDB / NanoVDB out. The exported files are decoded here by readers
// written from SymVox's own viewer (octree_dda.frag.glsl: child c = 4x + 2y + z, pointers in descending c,
// mirror bits X / Y / Z at 8 + c / 16 + c / 24 + c, index mirroring v' = M ? S - 1 - v : v; the 16-bit
// layout's codes, high-half-first pointers and 4^3 brick bit 16x + 4y + z), independently of megavox's
// decoders: a mirror on the wrong axis would keep the voxel count and move the voxels.
#include <nanovdb/util/IO.h>
#include <openvdb/openvdb.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "voxel/build_steps.h"
#include "io/symvox_file.h"
#include "reference.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/interop.h"
#include "megavox/mvx.h"
#include "test_support.h"
#include "option_words.h"

namespace mv::test {
namespace {

template <class T>
T at(const std::vector<char>& b, size_t offset) {
  T v;
  std::memcpy(&v, b.data() + offset, sizeof v);
  return v;
}

struct Voxel {
  uint32_t x, y, z;
};
using Emit = std::function<void(uint32_t, uint32_t, uint32_t)>;

uint32_t child_slot(uint32_t vx, uint32_t vy, uint32_t vz, uint32_t m) {  // m: bit 0 = X, 1 = Y, 2 = Z
  return 4 * (vx ^ (m & 1)) + 2 * (vy ^ (m >> 1 & 1)) + (vz ^ (m >> 2 & 1));
}

// SymVox 32-bit (.svdag / .ussvdag) from its viewer's rules.
void walk32(const uint32_t* w, uint32_t node, uint32_t level, uint32_t m, uint32_t x, uint32_t y, uint32_t z, const Emit& emit) {
  const uint32_t hdr = w[node], mask = hdr & 0xff, half = 1u << (level - 1);
  for (uint32_t v = 0; v < 8; ++v) {
    uint32_t vx = v >> 2 & 1, vy = v >> 1 & 1, vz = v & 1, c = child_slot(vx, vy, vz, m);
    if (!(mask >> c & 1)) continue;
    if (level == 1) {
      emit(x + vx, y + vy, z + vz);
      continue;
    }
    uint32_t ptr = w[node + __builtin_popcount(mask >> c)];
    uint32_t t = (hdr >> (8 + c) & 1) | (hdr >> (16 + c) & 1) << 1 | (hdr >> (24 + c) & 1) << 2;
    walk32(w, ptr, level - 1, m ^ t, x + vx * half, y + vy * half, z + vz * half, emit);
  }
}

// SymVox 16-bit (.ssvdag) from its viewer's rules.
struct Compact {
  std::vector<uint16_t> inner;
  std::vector<uint64_t> bricks;
  std::vector<uint32_t> offsets;  // per SymVox level, root level first
  uint32_t levels;
};
void walk16(const Compact& f, uint64_t node, uint32_t level, uint32_t m, uint32_t x, uint32_t y, uint32_t z,
            const Emit& emit) {
  const uint16_t hdr = f.inner[node];
  const uint32_t half = 1u << (level - 1);
  for (uint32_t v = 0; v < 8; ++v) {
    uint32_t vx = v >> 2 & 1, vy = v >> 1 & 1, vz = v & 1, c = child_slot(vx, vy, vz, m);
    uint32_t code = hdr >> (2 * c) & 3;
    if (!code) continue;
    uint64_t pos = node + 1;
    for (uint32_t k = c + 1; k < 8; ++k) pos += std::min<uint32_t>(hdr >> (2 * k) & 3, 2);
    uint32_t off, t;
    if (code == 1) {
      off = f.inner[pos] & 0x1fff;
      t = f.inner[pos] >> 13;
    } else {
      uint32_t p = uint32_t(f.inner[pos]) << 16 | f.inner[pos + 1];
      off = (p & 0x1fffffff) | (code & 1) << 29;
      t = p >> 29;
    }
    const uint32_t cm = m ^ t, cx = x + vx * half, cy = y + vy * half, cz = z + vz * half;
    if (level - 1 == 2) {
      const uint64_t brick = f.bricks.at(off);
      for (uint32_t ux = 0; ux < 4; ++ux)
        for (uint32_t uy = 0; uy < 4; ++uy)
          for (uint32_t uz = 0; uz < 4; ++uz) {
            uint32_t sx = cm & 1 ? 3 - ux : ux, sy = cm & 2 ? 3 - uy : uy, sz = cm & 4 ? 3 - uz : uz;
            if (brick >> (16 * sx + 4 * sy + sz) & 1) emit(cx + ux, cy + uy, cz + uz);
          }
    } else {
      walk16(f, f.offsets.at(f.levels - (level - 1)) + off, level - 1, cm, cx, cy, cz, emit);
    }
  }
}

// Voxels of a SymVox-family file, read the way SymVox's viewer reads it.
std::vector<uint64_t> symvox_viewer_voxels(const std::string& path) {
  std::vector<char> b = file_bytes(path);
  const uint32_t levels = at<uint32_t>(b, 28);
  std::vector<uint64_t> keys;
  Emit emit = [&](uint32_t x, uint32_t y, uint32_t z) { keys.push_back(ref::morton3(x, y, z, 21)); };
  const uint32_t words = at<uint32_t>(b, 40);
  if (b.size() == 44 + size_t{words} * 4) {
    std::vector<uint32_t> w(words);
    std::memcpy(w.data(), b.data() + 44, size_t{words} * 4);
    walk32(w.data(), 0, levels, 0, 0, 0, 0, emit);
  } else {
    Compact f;
    f.levels = levels;
    size_t p = 36;
    f.inner.resize(at<uint32_t>(b, p));
    std::memcpy(f.inner.data(), b.data() + p + 4, f.inner.size() * 2);
    p += 4 + f.inner.size() * 2;
    f.bricks.resize(at<uint32_t>(b, p) / 8);
    std::memcpy(f.bricks.data(), b.data() + p + 4, f.bricks.size() * 8);
    p += 4 + f.bricks.size() * 8;
    f.offsets.resize(at<uint32_t>(b, p));
    std::memcpy(f.offsets.data(), b.data() + p + 4, f.offsets.size() * 4);
    walk16(f, 0, levels, 0, 0, 0, 0, emit);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::string write_mvx_of(Device& dev, const std::vector<uint64_t>& keys, uint32_t levels, const std::string& format,
                         const std::string& name) {
  GridTransform g;
  g.resolution = 1u << levels;
  g.voxel_size = 0.5;
  g.origin[0] = -3;
  g.origin[1] = 1;
  g.origin[2] = 2;
  Bounds b;
  b.extend(-3, 1, 2);
  b.extend(-3 + 0.5 * g.resolution, 1 + 0.25 * g.resolution, 2 + 0.5 * g.resolution);
  const std::string path = temp_path(name);
  const Encoding encoding = parse_encoding(format);
  write_mvx(path, mvx_for_dag(build_dag_for_format(dev, keys, levels, encoding), encoding, g, b));
  return path;
}

const char* kLayouts[] = {"symvox-svdag", "symvox-ussvdag", "symvox-ssvdag"};

class SymVoxTest : public ::testing::TestWithParam<DeviceInfo> {};
class VdbExportTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(SymVoxTest, ExportsReadLikeSymVoxAndRoundTrip) {
  Device& dev = shared_device(GetParam());
  for (auto& [name, keys] : voxel_sets(6)) {
    for (const char* from : {"svdag", "ssvdag"}) {
      const std::string mvx = write_mvx_of(dev, keys, 6, from, "in.mvx");
      for (const char* layout : kLayouts) {
        const std::string file = temp_path("out.bin");  // no telling extension: import reads the content
        export_mvx(dev, {mvx, file, parse_export_format(layout)});
        EXPECT_TRUE(symvox_viewer_voxels(file) == keys) << name << " " << from << " -> " << layout;
        ImportReport r = import_symvox(dev, {file, temp_path("back.mvx"), SymvoxConvention::symvox, {}});
        if (std::string(layout) == "symvox-ssvdag") EXPECT_EQ(r.layout, "ssvdag");
        else EXPECT_TRUE(r.layout == "svdag" || r.layout == "ussvdag") << r.layout;
        MvxFile back = read_mvx(temp_path("back.mvx"));
        EXPECT_TRUE(decode_encoded(back.dag) == keys) << name << " " << from << " -> " << layout;
        EXPECT_NEAR(back.grid.origin[0], -3, 1e-5);
        EXPECT_NEAR(back.grid.origin[1], 1, 1e-5);
        EXPECT_NEAR(back.grid.origin[2], 2, 1e-5);
        EXPECT_NEAR(back.grid.voxel_size, 0.5, 1e-6);
      }
    }
  }
}

TEST_P(SymVoxTest, MirrorBitsAreUsed) {
  // The shell is full of mirror images: the .ussvdag must carry mirror bits and still read back exactly.
  Device& dev = shared_device(GetParam());
  auto sets = voxel_sets(6);
  const std::string mvx = write_mvx_of(dev, sets[1].second, 6, "ssvdag", "shell.mvx");
  export_mvx(dev, {mvx, temp_path("shell.ussvdag"), ExportFormat::symvox_ussvdag});
  io::SymvoxFile f = io::read_symvox(temp_path("shell.ussvdag"));
  EXPECT_EQ(f.dag.encoding, Encoding::ussvdag);
  EXPECT_EQ(f.levels, 6u);
}

TEST_P(SymVoxTest, VoxcomFilesAreRecognisedAndUntransposed) {
  // voxcom writes the 32-bit layout with Morton child order (x + 2y + 4z) and the cube at the bbox's min
  // corner in voxel units: read with SymVox's order that is the model with x and z swapped.
  Device& dev = shared_device(GetParam());
  auto keys = voxel_sets(5)[0].second;
  std::vector<uint64_t> swapped;
  for (uint64_t k : keys) {
    uint32_t x = 0, y = 0, z = 0;
    for (int i = 0; i < 21; ++i) {
      x |= uint32_t(k >> (3 * i) & 1) << i;
      y |= uint32_t(k >> (3 * i + 1) & 1) << i;
      z |= uint32_t(k >> (3 * i + 2) & 1) << i;
    }
    swapped.push_back(ref::morton3(z, y, x, 21));
  }
  std::sort(swapped.begin(), swapped.end());
  GridTransform g;
  g.resolution = 32;
  Bounds b;
  b.extend(0, 0, 0);
  b.extend(32, 20, 30);
  const std::string mvx = temp_path("vc.mvx");
  write_mvx(mvx, mvx_for_dag(build_dag_for_format(dev, swapped, 5, Encoding::svdag), Encoding::svdag, g, b));
  // A voxcom header: bbox from 0, root side = the resolution.
  export_mvx(dev, {mvx, temp_path("vc.svdag"), ExportFormat::symvox_svdag});
  std::vector<char> bytes = file_bytes(temp_path("vc.svdag"));
  const float box[7] = {0, 0, 0, 32, 20, 30, 32};
  std::memcpy(bytes.data(), box, sizeof box);
  write_bytes(temp_path("vc.svdag"), bytes);
  ImportReport r =
      import_symvox(dev, {temp_path("vc.svdag"), temp_path("vc_back.mvx"), SymvoxConvention::automatic, {}});
  EXPECT_EQ(r.convention, "voxcom");
  MvxFile back = read_mvx(temp_path("vc_back.mvx"));
  EXPECT_TRUE(decode_encoded(back.dag) == keys);
  EXPECT_DOUBLE_EQ(back.grid.origin[0], 0);
  EXPECT_DOUBLE_EQ(back.grid.voxel_size, 1);
  // The same file forced to SymVox's convention keeps the count and moves the voxels.
  import_symvox(dev, {temp_path("vc.svdag"), temp_path("vc_sym.mvx"), SymvoxConvention::symvox, {}});
  auto as_symvox = decode_encoded(read_mvx(temp_path("vc_sym.mvx")).dag);
  EXPECT_EQ(as_symvox.size(), keys.size());
  EXPECT_FALSE(as_symvox == keys);
}

TEST_P(SymVoxTest, CorruptAndTruncatedFilesAreClearErrors) {
  Device& dev = shared_device(GetParam());
  auto keys = voxel_sets(5)[1].second;
  const std::string mvx = write_mvx_of(dev, keys, 5, "ssvdag", "bad.mvx");
  std::mt19937 rng(9);
  for (const char* layout : kLayouts) {
    const std::string good = temp_path("good.bin"), bad = temp_path("bad.bin");
    export_mvx(dev, {mvx, good, parse_export_format(layout)});
    const std::vector<char> bytes = file_bytes(good);
    auto outcome = [&](const std::vector<char>& b) {
      write_bytes(bad, b);
      try {
        io::SymvoxFile f = io::read_symvox(bad);
        decode_encoded(f.dag);  // a valid file must decode
        return 1;
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()), "");
        return 0;
      }
    };
    EXPECT_EQ(outcome(bytes), 1) << layout;
    for (size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 97)  // every truncation fails
      EXPECT_EQ(outcome(std::vector<char>(bytes.begin(), bytes.begin() + cut)), 0) << layout << " cut at " << cut;
    for (int t = 0; t < 300; ++t) {  // random flips: an error or a valid file, never a crash
      std::vector<char> b = bytes;
      b[rng() % b.size()] ^= char(1u << (rng() % 8));
      outcome(b);
    }
    std::vector<char> extra = bytes;
    extra.push_back(0);
    EXPECT_EQ(outcome(extra), 0) << layout;
  }
  // A pointer back to the root (a cycle) and one past the end.
  export_mvx(dev, {mvx, temp_path("p.svdag"), ExportFormat::symvox_svdag});
  std::vector<char> b = file_bytes(temp_path("p.svdag"));
  for (uint32_t target : {0u, 0x7fffffffu}) {
    std::vector<char> c = b;
    std::memcpy(c.data() + 48, &target, 4);  // the root's first pointer
    write_bytes(temp_path("p_bad.svdag"), c);
    EXPECT_THROW(io::read_symvox(temp_path("p_bad.svdag")), Error) << target;
  }
  EXPECT_THROW(io::read_symvox(temp_path("no_such_file.svdag")), Error);
  write_bytes(temp_path("text.svdag"), std::vector<char>(100, 'x'));
  EXPECT_THROW(io::read_symvox(temp_path("text.svdag")), Error);
}

TEST_P(VdbExportTest, OpenVdbAndNanoVdbHoldTheSameActiveVoxels) {
  Device& dev = shared_device(GetParam());
  auto keys = voxel_sets(6)[1].second;
  const std::string mvx = write_mvx_of(dev, keys, 6, "svdag", "v.mvx");
  export_mvx(dev, {mvx, temp_path("v.vdb"), ExportFormat::vdb});
  export_mvx(dev, {mvx, temp_path("v.nvdb"), ExportFormat::nvdb});
  openvdb::initialize();
  openvdb::io::File file(temp_path("v.vdb"));
  file.open();
  auto grid = openvdb::gridPtrCast<openvdb::MaskGrid>(file.readGrid("voxels"));
  file.close();
  ASSERT_TRUE(grid);
  std::vector<uint64_t> got;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    openvdb::Coord c = it.getCoord();
    got.push_back(ref::morton3(uint32_t(c.x()), uint32_t(c.y()), uint32_t(c.z()), 21));
  }
  std::sort(got.begin(), got.end());
  EXPECT_TRUE(got == keys);
  // Voxel (0, 0, 0) covers [origin, origin + voxel): its centre maps to index 0.
  openvdb::Vec3d i = grid->transform().worldToIndex(openvdb::Vec3d(-3 + 0.25, 1 + 0.25, 2 + 0.25));
  EXPECT_NEAR(i.x(), 0, 1e-9);
  EXPECT_NEAR(i.z(), 0, 1e-9);

  auto handle = nanovdb::io::readGrid(temp_path("v.nvdb"));
  auto* nano = handle.grid<nanovdb::ValueMask>();
  ASSERT_NE(nano, nullptr);
  EXPECT_EQ(nano->activeVoxelCount(), keys.size());
  auto acc = nano->getAccessor();
  for (uint64_t k : keys) {
    uint32_t x = 0, y = 0, z = 0;
    for (int b = 0; b < 21; ++b) {
      x |= uint32_t(k >> (3 * b) & 1) << b;
      y |= uint32_t(k >> (3 * b + 1) & 1) << b;
      z |= uint32_t(k >> (3 * b + 2) & 1) << b;
    }
    ASSERT_TRUE(acc.isActive(nanovdb::Coord(int(x), int(y), int(z))));
  }
  // megavox reads its own export back.
  BuildOptions o;
  o.input = temp_path("v.vdb");
  o.output = temp_path("v_back.mvx");
  o.resolution = 64;
  BuildReport r = build_mvx(dev, o);
  EXPECT_EQ(r.voxels, keys.size());
  EXPECT_EQ(r.vdb_class, "mask");
  EXPECT_THROW(parse_export_format("obj"), CodedError);
}

MV_INSTANTIATE_ON_ALL_DEVICES(SymVoxTest);
MV_INSTANTIATE_ON_ALL_DEVICES(VdbExportTest);

}  // namespace
}  // namespace mv::test

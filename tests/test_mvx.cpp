// The svdag encoding and the .mvx container: round trips, and every kind of damage is a clear error.
#include <xxhash.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "reference.h"
#include "common/trace_nodes.h"
#include "megavox/dag.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

Dag sample_dag(Device& dev, std::vector<uint64_t>* voxels_out = nullptr) {
  std::mt19937_64 rng(9);
  std::vector<uint64_t> v;
  for (int i = 0; i < 2000; ++i) v.push_back(ref::morton3(rng() % 64, rng() % 64, (rng() % 8) * 8, 21));
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  if (voxels_out) *voxels_out = v;
  return build_svdag(dev, v, 6);
}

MvxFile sample_file(Device& dev, std::vector<uint64_t>* voxels = nullptr) {
  Dag dag = sample_dag(dev, voxels);
  MvxFile f;
  f.grid.resolution = 64;
  f.grid.voxel_size = 0.5;
  f.grid.origin[0] = -3;
  f.bounds.extend(-3, 0, 0);
  f.bounds.extend(29, 10, 20);
  f.voxels = dag.voxels;
  f.svo_nodes = dag.svo_nodes;
  f.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= dag.levels; ++l) f.dag_nodes.push_back(dag.nodes(l));
  f.dag = encode_svdag(dag);
  return f;
}

class SvdagTest : public ::testing::TestWithParam<DeviceInfo> {};
class MvxTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(SvdagTest, EncodesAndDecodesExactly) {
  std::vector<uint64_t> voxels;
  Dag dag = sample_dag(shared_device(GetParam()), &voxels);
  EncodedDag enc = encode_svdag(dag);
  uint64_t expect_words = dag.nodes(1);
  for (uint32_t l = 2; l <= dag.levels; ++l) expect_words += dag.nodes(l) + dag.level[l].children.size();
  EXPECT_EQ(enc.words.size(), expect_words);
  EXPECT_TRUE(decode_svdag(enc) == voxels);
  EXPECT_EQ(mv_xmajor_octant(1), 4u);  // Morton x bit -> x-major octant 4x + 2y + z
  EXPECT_EQ(mv_xmajor_octant(4), 1u);
  EXPECT_EQ(mv_xmajor_octant(2), 2u);
  for (uint32_t m = 0; m < 256; ++m) {  // masks: each bit to its x-major octant, and back
    uint32_t t = 0;
    for (uint32_t c = 0; c < 8; ++c) t |= (m >> c & 1) << mv_xmajor_octant(c);
    ASSERT_EQ(mv_xmajor_mask(m), t) << "mask " << m;
    ASSERT_EQ(mv_xmajor_mask(t), m) << "mask " << m;
  }
}

TEST_P(SvdagTest, RejectsBadPointersAndHeaders) {
  EncodedDag enc = encode_svdag(sample_dag(shared_device(GetParam())));
  EncodedDag bad = enc;
  bad.words[1] = bad.words[1] + 1;  // the root's first pointer: no longer a node start
  EXPECT_THROW(validate_svdag(bad), Error);
  bad = enc;
  bad.words[1] = 0;  // points back at the root: a cycle
  EXPECT_THROW(validate_svdag(bad), Error);
  bad = enc;
  bad.words[0] = 0;  // empty header
  EXPECT_THROW(validate_svdag(bad), Error);
  bad = enc;
  bad.words.pop_back();  // a leaf missing
  EXPECT_THROW(validate_svdag(bad), Error);
}

TEST_P(MvxTest, RoundTrip) {
  std::vector<uint64_t> voxels;
  MvxFile f = sample_file(shared_device(GetParam()), &voxels);
  const std::string p = temp_path("roundtrip.mvx");
  write_mvx(p, f);
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  EXPECT_EQ(fs::file_size(p) % 4096, 0u);
  MvxFile g = read_mvx(p);
  EXPECT_EQ(g.voxels, f.voxels);
  EXPECT_EQ(g.svo_nodes, f.svo_nodes);
  EXPECT_EQ(g.dag_nodes, f.dag_nodes);
  EXPECT_EQ(g.grid.resolution, 64u);
  EXPECT_EQ(g.grid.voxel_size, 0.5);
  EXPECT_EQ(g.bounds.hi[2], 20);
  EXPECT_TRUE(decode_svdag(g.dag) == voxels);
  fs::remove(p);
}

TEST_P(MvxTest, DamageIsAClearError) {
  MvxFile f = sample_file(shared_device(GetParam()));
  const std::string p = temp_path("damage.mvx");
  write_mvx(p, f);
  const std::vector<char> good = file_bytes(p);
  const std::string q = temp_path("damaged.mvx");
  auto expect_error = [&](const std::vector<char>& bytes, const std::string& words) {
    write_bytes(q, bytes);
    try {
      read_mvx(q);
      ADD_FAILURE() << "no error for damage expected to say '" << words << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  std::vector<char> b = good;
  b[0] = 'X';
  expect_error(b, "bad magic");
  expect_error(std::vector<char>(good.begin(), good.begin() + 100), "truncated");
  expect_error(std::vector<char>(good.begin(), good.end() - 4096), "truncated");
  b = good;
  b[40] ^= 1;  // inside the header
  expect_error(b, "header checksum");
  b = good;
  b[4096 + 3] ^= 1;  // inside the counts section
  expect_error(b, "checksum mismatch in the counts section");
  b = good;
  b[b.size() - 4096 - 1] ^= 0;  // padding is not checked; a flip in the nodes is:
  b[3 * 4096 + 4] ^= 0x10;  // paged (version 3): each page has its hash in the page index
  expect_error(b, "checksum mismatch in page 0 of the nodes");
  // Every single-byte flip of the header page fails cleanly or is harmless padding.
  for (size_t i = 0; i < 4096; i += 7) {
    b = good;
    b[i] ^= 0x5a;
    write_bytes(q, b);
    try {
      read_mvx(q);
    } catch (const Error&) {
    }
  }
  // Every truncation is an error.
  for (size_t n = 0; n < good.size(); n += 997) {
    write_bytes(q, std::vector<char>(good.begin(), good.begin() + n));
    EXPECT_THROW(read_mvx(q), Error) << "truncated to " << n;
  }
  EXPECT_THROW(read_mvx(temp_path("no_such_file.mvx")), Error);
  fs::remove(p);
  fs::remove(q);
}

TEST_P(MvxTest, ValidChecksumsButBadPointersAreCaught) {
  MvxFile f = sample_file(shared_device(GetParam()));
  f.dag.words[1] = 0;  // a cycle, written with correct checksums (unpaged: paging validates the stream first)
  const std::string p = temp_path("cycle.mvx");
  EXPECT_NE(error_message([&] { write_mvx(p, f); }).find("points to"), std::string::npos);
  write_mvx(p, f, {0, NodeOrder::level});
  try {
    read_mvx(p);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("points to"), std::string::npos) << e.what();
  }
  fs::remove(p);
}

TEST_P(MvxTest, UnwritablePathIsAnErrorAndLeavesNothing) {
  EXPECT_THROW(write_mvx("/nonexistent-dir/x.mvx", sample_file(shared_device(GetParam()))), Error);
  EXPECT_FALSE(fs::exists("/nonexistent-dir/x.mvx.tmp"));
}

MV_INSTANTIATE_ON_ALL_DEVICES(SvdagTest);
MV_INSTANTIATE_ON_ALL_DEVICES(MvxTest);

}  // namespace
}  // namespace mv::test

namespace mv::test {
namespace {

class UssvdagTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(UssvdagTest, EncodesAndDecodesExactly) {
  std::mt19937_64 rng(4);
  std::vector<uint64_t> v;
  for (int i = 0; i < 3000; ++i) {  // a model mirrored in x: many mirrored subtrees
    uint32_t x = rng() % 32, y = rng() % 64, z = rng() % 64;
    v.push_back(ref::morton3(x, y, z, 21));
    v.push_back(ref::morton3(63 - x, y, z, 21));
  }
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  Device& dev = shared_device(GetParam());
  Dag sym = build_ssvdag(dev, v, 6);
  Dag plain = build_svdag(dev, v, 6);
  EncodedDag enc = encode_svdag(sym);
  EXPECT_EQ(enc.encoding, Encoding::ussvdag);
  EXPECT_LT(enc.words.size(), encode_svdag(plain).words.size());
  EXPECT_TRUE(decode_svdag(enc) == v);
  if ((enc.words[0] & 0xff) != 0xff) {  // a mirror bit on a missing child (ctz of 0 is UB: UBSan found it)
    EncodedDag bad = enc;
    bad.words[0] |= 1u << 8 << __builtin_ctz(~bad.words[0] & 0xff);
    EXPECT_THROW(validate_svdag(bad), Error);
  }
  // Through the file.
  MvxFile f;
  f.grid.resolution = 64;
  f.voxels = sym.voxels;
  f.svo_nodes = sym.svo_nodes;
  f.dag_nodes.assign(7, 1);
  f.dag = enc;
  const std::string p = temp_path("ussvdag.mvx");
  write_mvx(p, f);
  MvxFile g = read_mvx(p);
  EXPECT_EQ(g.dag.encoding, Encoding::ussvdag);
  EXPECT_TRUE(decode_svdag(g.dag) == v);
  std::filesystem::remove(p);
}

MV_INSTANTIATE_ON_ALL_DEVICES(UssvdagTest);

}  // namespace
}  // namespace mv::test

namespace mv::test {
namespace {

class SsvdagTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(SsvdagTest, CompactEncodingDecodesExactly) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(12);
  for (uint32_t levels : {3u, 5u, 7u}) {
    const uint32_t n = 1u << levels;
    std::vector<uint64_t> v;
    for (int i = 0; i < 4000; ++i) {
      uint32_t x = rng() % (n / 2), y = rng() % n, z = rng() % n;
      v.push_back(ref::morton3(x, y, z, 21));
      if (i % 3) v.push_back(ref::morton3(n - 1 - x, y, z, 21));
    }
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    Dag sym = build_ssvdag(dev, v, levels);
    EncodedDag enc = encode_ssvdag(sym);
    EXPECT_EQ(enc.bricks.size(), sym.nodes(2));
    EXPECT_TRUE(decode_ssvdag(enc) == v) << "levels " << levels;
    EXPECT_LT(enc.bytes(), encode_svdag(build_svdag(dev, v, levels)).bytes());
    const std::string p = temp_path("ssvdag.mvx");
    MvxFile f;
    f.grid.resolution = n;
    f.voxels = sym.voxels;
    f.svo_nodes = sym.svo_nodes;
    f.dag_nodes.assign(levels + 1, 1);
    f.dag = enc;
    write_mvx(p, f);
    EXPECT_TRUE(decode_encoded(read_mvx(p).dag) == v);
    std::filesystem::remove(p);
  }
}

TEST_P(SsvdagTest, RejectsDamage) {
  Device& dev = shared_device(GetParam());
  std::vector<uint64_t> v;
  for (uint32_t x = 0; x < 64; x += 3) v.push_back(ref::morton3(x, x / 2, 63 - x, 21));
  std::sort(v.begin(), v.end());
  EncodedDag enc = encode_ssvdag(build_ssvdag(dev, v, 6));
  EncodedDag bad = enc;
  bad.inner[0] = 0;  // empty root
  EXPECT_THROW(validate_ssvdag(bad), Error);
  bad = enc;
  bad.bricks.pop_back();  // a pointer to a missing brick
  EXPECT_THROW(validate_ssvdag(bad), Error);
  bad = enc;
  bad.inner.pop_back();  // a node cut short
  EXPECT_THROW(validate_ssvdag(bad), Error);
  EXPECT_THROW(encode_ssvdag(build_ssvdag(dev, {0}, 2)), Error);
}

MV_INSTANTIATE_ON_ALL_DEVICES(SsvdagTest);

}  // namespace
}  // namespace mv::test

namespace mv::test {
namespace {

// The whole build on every device gives the same encoded bytes (discrete results are backend-independent).
// At 512^3 the levels above 2 hold several thousand nodes: PoCL walks them in contiguous blocks (reusing a
// run's results), lavapipe one node per invocation.
TEST(Build, EveryDeviceWritesTheSameBytes) {
  if (all_devices().empty()) GTEST_SKIP() << "no device (see Environment.SomeDeviceIsFound)";
  std::vector<float> tris = octahedron_grid_triangles(512);
  std::vector<std::vector<uint32_t>> svdag, ussvdag;
  std::vector<std::vector<uint16_t>> ssvdag;
  for (const DeviceInfo& d : all_devices()) {
    Device& dev = shared_device(d);
    Voxelizer v(dev, 512);
    v.add(tris);
    std::vector<uint64_t> voxels = v.take_keys();
    svdag.push_back(encode_svdag(build_svdag(dev, voxels, 9)).words);
    Dag sym = build_ssvdag(dev, voxels, 9);
    ussvdag.push_back(encode_svdag(sym).words);
    ssvdag.push_back(encode_ssvdag(sym).inner);
  }
  for (size_t i = 1; i < svdag.size(); ++i) {
    EXPECT_TRUE(svdag[i] == svdag[0]) << all_devices()[i].selector();
    EXPECT_TRUE(ussvdag[i] == ussvdag[0]) << all_devices()[i].selector();
    EXPECT_TRUE(ssvdag[i] == ssvdag[0]) << all_devices()[i].selector();
  }
}

// Axis-aligned planes at 512^3 with random holes: thousands of nodes per level with symmetric masks and
// differing children, so candidate reflections are compared entry by entry (long inner loops per node, in
// blocks on PoCL; llvmpipe caps a loop's iterations per invocation).
TEST(Build, EveryDeviceReducesLargeHoledPlanesAlike) {
  if (all_devices().empty()) GTEST_SKIP() << "no device (see Environment.SomeDeviceIsFound)";
  const uint32_t n = 512;
  std::mt19937 rng(7);
  std::vector<uint64_t> voxels;
  for (uint32_t a = 0; a < n; ++a)
    for (uint32_t b = 0; b < n; ++b) {
      if (rng() % 10 < 7) voxels.push_back(ref::morton3(n / 4, a, b, 21));
      if (rng() % 10 < 7) voxels.push_back(ref::morton3(a, 3, b, 21));
      if (a < n / 2 && rng() % 10 < 7) voxels.push_back(ref::morton3(a, b, n - 2, 21));
    }
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  std::vector<std::vector<uint16_t>> ssvdag;
  for (const DeviceInfo& d : all_devices()) ssvdag.push_back(encode_ssvdag(build_ssvdag(shared_device(d), voxels, 9)).inner);
  for (size_t i = 1; i < ssvdag.size(); ++i) EXPECT_TRUE(ssvdag[i] == ssvdag[0]) << all_devices()[i].selector();
}

}  // namespace
}  // namespace mv::test

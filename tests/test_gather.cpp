// The record gather and the point bounds on every device vs plain loops (gather_reference.h): records of every
// width from a byte to 16 bytes (units of 1, 2 and 4 bytes, records that straddle output words), repeated and
// reversed indices, and bounds at the ends of the int32 range.
#include <random>

#include "gather_reference.h"
#include "megavox/primitives.h"
#include "points/point_gather.h"
#include "points/point_kernels.h"
#include "test_support.h"

namespace mv::test {
namespace {

class GatherTest : public ::testing::TestWithParam<DeviceInfo> {};

std::vector<uint8_t> device_gather(Device& dev, const std::vector<uint8_t>& src, const std::vector<uint32_t>& index,
                                   uint32_t record_bytes) {
  const uint64_t out_bytes = index.size() * record_bytes;
  Buffer sb = dev.alloc(std::max<uint64_t>((src.size() + 3) / 4 * 4, 4), "records");
  Buffer ib = dev.alloc(std::max<uint64_t>(index.size() * 4, 4), "record index");
  Buffer db = dev.alloc(std::max<uint64_t>((out_bytes + 3) / 4 * 4, 4), "gathered records");
  if (!src.empty()) dev.upload(sb, src.data(), src.size());
  if (!index.empty()) dev.upload(ib, index.data(), index.size() * 4);
  dev.barrier();
  gather_records(dev, sb, ib, db, index.size(), record_bytes);
  std::vector<uint8_t> out(out_bytes);
  dev.finish();
  if (out_bytes) dev.download(db, out.data(), out_bytes);
  return out;
}

TEST_P(GatherTest, RecordsOfEveryWidthMatchTheReference) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(5);
  for (uint32_t record_bytes : {1u, 2u, 3u, 4u, 6u, 7u, 12u, 16u})
    for (size_t records : {size_t{1}, size_t{2}, size_t{5}, size_t{1000}, size_t{100003}})
      for (size_t n : {size_t{0}, size_t{1}, size_t{3}, records, 2 * records + 1}) {
        std::vector<uint8_t> src(records * record_bytes);
        for (uint8_t& b : src) b = static_cast<uint8_t>(rng());
        std::vector<uint32_t> index(n);
        for (size_t i = 0; i < n; ++i) index[i] = static_cast<uint32_t>(i % 3 == 2 ? records - 1 - i % records : rng() % records);
        EXPECT_EQ(device_gather(dev, src, index, record_bytes), ref::gather_records(src, index, record_bytes))
            << record_bytes << "-byte records, " << records << " of them, " << n << " gathered";
      }
}

// A source in slices, one pass each: the passes together write what one pass over the whole source would.
TEST_P(GatherTest, SlicedSourcesMatchOnePass) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(7);
  for (uint32_t record_bytes : {1u, 3u, 6u, 12u}) {
    const size_t records = 5003, n = 12011;
    std::vector<uint8_t> src(records * record_bytes);
    for (uint8_t& b : src) b = static_cast<uint8_t>(rng());
    std::vector<uint32_t> index(n);
    for (uint32_t& i : index) i = static_cast<uint32_t>(rng() % records);
    const uint64_t out_bytes = n * record_bytes;
    Buffer ib = dev.alloc(n * 4, "record index");
    Buffer db = dev.alloc((out_bytes + 3) / 4 * 4, "gathered records");
    dev.upload(ib, index.data(), n * 4);
    const uint32_t slice = 1237;
    for (uint32_t first = 0; first < records; first += slice) {
      const uint32_t count = std::min<uint32_t>(slice, static_cast<uint32_t>(records) - first);
      Buffer sb = dev.alloc((uint64_t{count} * record_bytes + 3) / 4 * 4, "record slice");
      dev.upload(sb, src.data() + uint64_t{first} * record_bytes, uint64_t{count} * record_bytes);
      dev.barrier();
      gather_records(dev, sb, ib, db, n, record_bytes, {first, count, first > 0});
      dev.finish();
    }
    std::vector<uint8_t> out(out_bytes);
    dev.download(db, out.data(), out_bytes);
    EXPECT_EQ(out, ref::gather_records(src, index, record_bytes)) << record_bytes << "-byte records";
  }
}

TEST_P(GatherTest, PointBoundsMatchTheReference) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(9);
  for (size_t n : {size_t{1}, size_t{2}, size_t{63}, size_t{65}, size_t{40000}, size_t{300001}}) {
    std::vector<int32_t> xyz(3 * n);
    for (int32_t& v : xyz) v = static_cast<int32_t>(rng() % 2000001) - 1000000;
    if (n > 40000) {  // the ends of the range, far inside the points
      xyz[3 * (n / 2)] = INT32_MIN;
      xyz[3 * (n / 3) + 2] = INT32_MAX;
    }
    int64_t lo[3], hi[3];
    mv::points::point_bounds(dev, xyz, lo, hi);
    const std::array<int64_t, 6> want = ref::point_bounds(xyz);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(lo[a], want[a]) << n << " points, axis " << a;
      EXPECT_EQ(hi[a], want[3 + a]) << n << " points, axis " << a;
    }
  }
}

// Random columns (every kind, 3 extra bytes a point), a random permutation as the sort's, and node sources that
// mix leaf runs and representatives, in chunks of a few records and in one.
struct NodeCase {
  PointColumns points;
  std::vector<uint32_t> index;
  std::vector<mv::points::NodePoints> sources;
  std::vector<uint64_t> reps;
};

NodeCase node_case(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  NodeCase c;
  for (size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      c.points.xyz.push_back(static_cast<int32_t>(rng()));
      c.points.rgb.push_back(static_cast<uint16_t>(rng()));
      c.points.normal.push_back(static_cast<float>(rng() % 1000) / 7.0f);
      c.points.extra.push_back(static_cast<uint8_t>(rng()));
    }
    c.points.intensity.push_back(static_cast<uint16_t>(rng()));
    c.index.push_back(static_cast<uint32_t>(i));
  }
  std::shuffle(c.index.begin(), c.index.end(), rng);
  for (uint64_t at = 0; at < n;) {  // leaves cover the sorted points; an inner node after every few
    const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(1 + rng() % 40, n - at));
    c.sources.push_back({at, count, false});
    at += count;
    if (rng() % 3 == 0) {
      const uint32_t picks = static_cast<uint32_t>(rng() % 9);
      c.sources.push_back({c.reps.size(), picks, true});
      for (uint32_t k = 0; k < picks; ++k) c.reps.push_back(rng() % n);
    }
  }
  return c;
}

void check_node_gather(Device& dev, const NodeCase& c, uint64_t chunk, uint64_t slice = 0) {
  std::vector<uint32_t> order;  // input position of every node-order point
  for (const mv::points::NodePoints& s : c.sources)
    for (uint32_t i = 0; i < s.count; ++i) order.push_back(c.index[s.reps ? c.reps[s.first + i] : s.first + i]);
  PointColumns copy = c.points;
  const PointColumns got = mv::points::gather_node_points(dev, std::move(copy), c.index, c.sources, c.reps, 3, chunk, slice);
  auto bytes = [](const auto& v) {
    return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v.data()), v.size() * sizeof(v[0]));
  };
  EXPECT_EQ(bytes(got.xyz).size(), order.size() * 12);
  EXPECT_TRUE(std::ranges::equal(bytes(got.xyz), ref::gather_records(bytes(c.points.xyz), order, 12))) << chunk;
  EXPECT_TRUE(std::ranges::equal(bytes(got.rgb), ref::gather_records(bytes(c.points.rgb), order, 6))) << chunk;
  EXPECT_TRUE(std::ranges::equal(bytes(got.normal), ref::gather_records(bytes(c.points.normal), order, 12))) << chunk;
  EXPECT_TRUE(std::ranges::equal(bytes(got.intensity), ref::gather_records(bytes(c.points.intensity), order, 2)))
      << chunk;
  EXPECT_TRUE(std::ranges::equal(bytes(got.extra), ref::gather_records(bytes(c.points.extra), order, 3))) << chunk;
}

TEST_P(GatherTest, NodeOrderColumnsMatchTheReference) {
  Device& dev = shared_device(GetParam());
  for (size_t n : {size_t{1}, size_t{7}, size_t{5000}}) {
    const NodeCase c = node_case(n, n);
    for (uint64_t chunk : {uint64_t{4}, uint64_t{36}, uint64_t{0}}) check_node_gather(dev, c, chunk);
    for (uint64_t slice : {uint64_t{3}, uint64_t{999}})  // sources in slices
      if (n <= 7 || slice > 3) check_node_gather(dev, c, n <= 7 ? 4 : 1024, slice);
  }
}

// A device whose budget cannot hold the columns: the host gathers them, the same bytes.
TEST_P(GatherTest, NodeOrderColumnsOnTheHostWhereTheDeviceCannotHoldThem) {
  DeviceOptions o;
  o.selector = GetParam().selector();
  o.memory_budget = 4u << 20;
  std::unique_ptr<Device> dev = Device::open(o);
  check_node_gather(*dev, node_case(200000, 3), 0);
}

MV_INSTANTIATE_ON_ALL_DEVICES(GatherTest);

}  // namespace
}  // namespace mv::test

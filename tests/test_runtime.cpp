// Device discovery, selection and kernel build errors.
#include <cstdlib>

#include "common/morton.h"
#include "megavox/error.h"
#include "reference.h"
#include "test_kernels.h"
#include "test_support.h"

namespace mv::test {
namespace {

bool has_device(const std::string& backend, const std::string& needle) {
  for (const auto& d : all_devices()) {
    std::string hay = d.name + " " + d.platform;
    for (auto& c : hay) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (d.backend == backend && hay.find(needle) != std::string::npos) return true;
  }
  return false;
}

// Every device suite runs on each device found; with none, this is the test that says so.
TEST(Environment, SomeDeviceIsFound) {
  EXPECT_FALSE(all_devices().empty())
      << "no OpenCL or Vulkan device found: install pocl-opencl-icd / mesa-vulkan-drivers (scripts/setup.sh)";
}

// The CPU devices CI relies on. MEGAVOX_EXPECT_DEVICES=none turns this off on machines that lack them.
TEST(Environment, ExpectedCpuDevicesArePresent) {
  const char* expect = std::getenv("MEGAVOX_EXPECT_DEVICES");
  if (expect && std::string(expect) == "none") GTEST_SKIP() << "MEGAVOX_EXPECT_DEVICES=none";
  EXPECT_TRUE(has_device("opencl", "portable computing language") || has_device("opencl", "pocl"))
      << "PoCL (OpenCL on the CPU) is missing: install pocl-opencl-icd (scripts/setup.sh does)";
  EXPECT_TRUE(has_device("vulkan", "llvmpipe"))
      << "lavapipe (Vulkan on the CPU) is missing: install mesa-vulkan-drivers (scripts/setup.sh does)";
}

TEST(Selection, UnknownSelectorListsDevices) {
  try {
    select_device("no-such-device");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("no device matches 'no-such-device'"), std::string::npos) << msg;
    for (const auto& d : all_devices()) EXPECT_NE(msg.find(d.selector()), std::string::npos) << msg;
  }
  EXPECT_THROW(select_device("ocl:999"), Error);
  EXPECT_THROW(select_device("vk:x"), Error);
}

TEST(Selection, ByIndexAndByName) {
  for (const auto& d : all_devices()) {
    DeviceInfo s = select_device(d.selector());
    EXPECT_EQ(s.backend, d.backend);
    EXPECT_EQ(s.index, d.index);
  }
  if (has_device("opencl", "pocl") || has_device("opencl", "portable")) {
    EXPECT_EQ(select_device("pocl").backend, "opencl");
  }
  if (has_device("vulkan", "llvmpipe")) {
    EXPECT_EQ(select_device("LLVMPIPE").backend, "vulkan");
  }
}

TEST(Selection, DefaultPrefersGpuThenPocl) {
  unsetenv("MEGAVOX_DEVICE");
  if (all_devices().empty()) {  // then the default is a clear error
    EXPECT_THROW(select_device(""), Error);
    return;
  }
  DeviceInfo d = select_device("");
  bool any_gpu = false;
  for (const auto& x : all_devices()) any_gpu |= x.type == "gpu";
  if (any_gpu) EXPECT_EQ(d.type, "gpu");
  else EXPECT_EQ(d.backend, "opencl");
}

TEST(Sizes, ParseAndFormat) {
  EXPECT_EQ(parse_size("1048576"), 1048576u);
  EXPECT_EQ(parse_size("16K"), 16u << 10);
  EXPECT_EQ(parse_size("512M"), 512u << 20);
  EXPECT_EQ(parse_size("2G"), 2ull << 30);
  EXPECT_EQ(parse_size("2GiB"), 2ull << 30);
  EXPECT_THROW(parse_size(""), Error);
  EXPECT_THROW(parse_size("abc"), Error);
  EXPECT_THROW(parse_size("12Q"), Error);
  EXPECT_THROW(parse_size("99999999999999999999"), Error);
  EXPECT_THROW(parse_size("99999999999T"), Error);
  EXPECT_EQ(format_bytes(512u << 20), "512.0 MiB");
}

class RuntimeTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }
};

TEST_P(RuntimeTest, UploadFillCopyDownload) {
  Device& d = dev();
  std::vector<uint32_t> data = random_u32(100000, 1);
  Buffer a = d.alloc(data.size() * 4, "a");
  Buffer b = d.alloc(data.size() * 4, "b");
  d.upload(a, data.data(), data.size() * 4);
  d.fill(b, 0x01020304, data.size() * 4);
  d.barrier();
  d.copy(a, b, 4000 * 4, 1000 * 4, 2000 * 4);
  d.finish();
  std::vector<uint32_t> got(data.size());
  d.download(b, got.data(), got.size() * 4);
  for (size_t i = 0; i < got.size(); ++i) {
    uint32_t expect = (i >= 2000 && i < 6000) ? data[i - 1000] : 0x01020304u;
    ASSERT_EQ(got[i], expect) << "at " << i;
  }
  EXPECT_THROW(d.download(a, got.data(), 8, data.size() * 4), Error);  // out of range
}

// Asynchronous uploads run in order with the other commands: a fill before, an upload over part of it, a copy
// after that reads it, all recorded without a wait; the source may change only after finish().
TEST_P(RuntimeTest, AsynchronousUploadsRunInStreamOrder) {
  Device& d = dev();
  std::vector<uint32_t> data = random_u32(50000, 2), more = random_u32(1000, 3);
  Buffer a = d.alloc(data.size() * 4, "a");
  Buffer b = d.alloc(data.size() * 4, "b");
  d.fill(a, 7, data.size() * 4);
  d.barrier();
  d.upload_async(a, data.data() + 100, 20000 * 4, 100 * 4);
  d.upload_async(a, more.data(), more.size() * 4, 30000 * 4);
  d.barrier();
  d.copy(a, b, data.size() * 4);
  d.finish();
  std::vector<uint32_t> got(data.size());
  d.download(b, got.data(), got.size() * 4);
  for (size_t i = 0; i < got.size(); ++i) {
    const uint32_t expect = i >= 100 && i < 20100 ? data[i] : i >= 30000 && i < 31000 ? more[i - 30000] : 7u;
    ASSERT_EQ(got[i], expect) << "at " << i;
  }
  EXPECT_THROW(d.upload_async(a, data.data(), 8, data.size() * 4), Error);  // out of range
}

// Stream marks: work submitted in parts runs while the host goes on. Waiting for a mark makes the work before it
// readable (in place where the device has host views) and frees what it read (an asynchronous upload's source
// may change then), while later parts finish at their own marks.
TEST_P(RuntimeTest, StreamMarksWaitForTheWorkBeforeThem) {
  Device& d = dev();
  constexpr int kParts = 4;
  constexpr uint32_t kPoints = 1 << 15;
  std::vector<std::vector<uint32_t>> xyz(kParts);
  std::vector<Buffer> pts(kParts), keys(kParts);
  std::vector<Device::StreamMark> marks;
  Kernel& morton = d.kernel(KernelId::morton_encode64);
  for (int part = 0; part < kParts; ++part) {
    xyz[part] = random_u32(3 * kPoints, 10 + part);
    for (uint32_t& c : xyz[part]) c &= 0x1fffff;
    pts[part] = d.alloc(xyz[part].size() * 4, "points");
    keys[part] = d.alloc(uint64_t{kPoints} * 8, "keys");
    d.upload_async(pts[part], xyz[part].data(), xyz[part].size() * 4);
    d.barrier();
    d.dispatch(morton, kPoints / 64, 64, {&pts[part], &keys[part]}, MvMortonParams{kPoints, 0});
    d.barrier();
    marks.push_back(d.submit());
    if (part > 0) EXPECT_GT(marks[part], marks[part - 1]);
  }
  auto expect_keys = [&](int part, const uint64_t* got, const std::vector<uint32_t>& from) {
    for (uint32_t i = 0; i < kPoints; ++i)
      ASSERT_EQ(got[i], ref::morton3(from[3 * i], from[3 * i + 1], from[3 * i + 2], 21)) << "part " << part << " at " << i;
  };
  d.wait(marks[1]);
  d.wait(marks[0]);  // already reached: returns at once
  std::vector<std::vector<uint32_t>> sent = {xyz[0], xyz[1]};
  for (int part = 0; part < 2; ++part) {
    std::fill(xyz[part].begin(), xyz[part].end(), 0xdeadbeefu);  // the uploads that read them are done
    if (const void* view = d.host_view(keys[part])) expect_keys(part, static_cast<const uint64_t*>(view), sent[part]);
  }
  d.wait(marks[kParts - 1]);
  sent.push_back(xyz[2]);
  sent.push_back(xyz[3]);
  std::vector<uint64_t> got(kPoints);
  for (int part = 0; part < kParts; ++part) {
    d.download(keys[part], got.data(), got.size() * 8);
    expect_keys(part, got.data(), sent[part]);
  }
  const Device::StreamMark last = d.submit();  // nothing new recorded: a mark all the same
  EXPECT_GE(last, marks.back());
  d.wait(last);
  EXPECT_THROW(d.wait(last + 1000), Error);
  d.finish();
}

TEST_P(RuntimeTest, UnknownKernelIsAnError) { EXPECT_THROW(dev().kernel(static_cast<KernelId>(kKernelCount)), Error); }

// Every kernel kernels/kernels.cmake and tests/kernels/kernels.cmake list builds on every device that has what
// it needs, and its OpenCL source takes the arguments the list declares (the backend compares them when the
// kernel is built).
TEST_P(RuntimeTest, EveryKernelBuildsWithItsDeclaredSignature) {
  const auto builds = [](auto&& build) {
    try {
      build();
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("is unsuitable for kernel"), std::string::npos) << msg;  // only a missing feature
    }
  };
  for (uint32_t id = 0; id < kKernelCount; ++id) builds([&] { dev().kernel(static_cast<KernelId>(id)); });
  for (uint32_t id = 0; id < kTestKernelCount; ++id) builds([&] { test_kernel(dev(), static_cast<TestKernelId>(id)); });
}

// The library's table holds only the kernels it ships: the tests' own are in a table of their own.
TEST(KernelTable, HoldsNoTestKernels) {
  for (uint32_t id = 0; id < kKernelCount; ++id) {
    const std::string name = rt::find_embedded_kernel(static_cast<KernelId>(id))->name;
    for (uint32_t t = 0; t < kTestKernelCount; ++t)
      EXPECT_NE(name, rt::find_test_kernel(static_cast<TestKernelId>(t))->name);
  }
}

// A dispatch whose buffer count or parameter struct differs from kernels/kernels.cmake fails before it
// reaches the backend, with the kernel's name, on every backend.
TEST_P(RuntimeTest, DispatchChecksTheDeclaredSignature) {
  Device& d = dev();
  Kernel& k = d.kernel(KernelId::morton_encode64);
  Buffer a = d.alloc(64, "a");
  auto message = [&](auto&& dispatch) {
    try {
      dispatch();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const MvMortonParams p{0, 0};
  std::string wrong_count = message([&] { d.dispatch(k, 1, 1, {&a}, p); });
  EXPECT_NE(wrong_count.find("kernel 'morton_encode64': dispatched with 1 buffers"), std::string::npos) << wrong_count;
  EXPECT_NE(wrong_count.find("declares 2"), std::string::npos) << wrong_count;
  struct SameSizeOtherType {
    uint32_t a, b;
  } other{0, 0};
  std::string wrong_type = message([&] { d.dispatch(k, 1, 1, {&a, &a}, other); });
  EXPECT_NE(wrong_type.find("kernel 'morton_encode64'"), std::string::npos) << wrong_type;
  EXPECT_NE(wrong_type.find("MvMortonParams"), std::string::npos) << wrong_type;
  const uint32_t too_small = 0;
  std::string wrong_size = message([&] { d.dispatch_raw(k, 1, 1, {&a, &a}, &too_small, sizeof(too_small)); });
  EXPECT_NE(wrong_size.find("kernel 'morton_encode64': dispatched with 4 parameter bytes"), std::string::npos)
      << wrong_size;
  d.dispatch(k, 1, 1, {&a, &a}, p);  // the declared signature goes through
  d.finish();
}

TEST_P(RuntimeTest, BuildErrorsNameTheKernel) {
  Device& d = dev();
  const uint32_t garbage[] = {0xdeadbeef, 1, 2, 3, 4, 5};
  static const char* bad_cl = "__kernel void broken_kernel(__global uint* a) { a[0] = undefined_symbol; }\n";
  try {
    d.kernel_from_source("broken_kernel", bad_cl, garbage, 6);
    FAIL() << "expected a build error";
  } catch (const Error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("broken_kernel"), std::string::npos) << msg;
    if (GetParam().backend == "opencl") {  // the compiler's own log is surfaced
      EXPECT_NE(msg.find("undefined_symbol"), std::string::npos) << msg;
    }
  }
}

TEST_P(RuntimeTest, ProfilingReportsKernelTimes) {
  auto d = Device::open({GetParam().selector(), 64u << 20, true});
  std::vector<uint64_t> keys = random_u64(1 << 16, 4);
  Buffer kb = d->alloc(keys.size() * 8, "keys");
  d->upload(kb, keys.data(), keys.size() * 8);
  std::vector<uint32_t> xyz(3 * 1000, 7);
  Buffer pts = d->alloc(xyz.size() * 4, "points");
  d->upload(pts, xyz.data(), xyz.size() * 4);
  MvMortonParams p{1000, 0};
  d->dispatch(d->kernel(KernelId::morton_encode64), 16, 64, {&pts, &kb}, p);
  d->finish();
  auto t = d->take_timings();
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].kernel, "morton_encode64");
  EXPECT_EQ(t[0].work_items, 16u * 64u);
  EXPECT_TRUE(d->take_timings().empty());
  // Dispatches of several submissions are all timed.
  d->dispatch(d->kernel(KernelId::morton_encode64), 16, 64, {&pts, &kb}, p);
  d->wait(d->submit());
  d->dispatch(d->kernel(KernelId::morton_encode64), 16, 64, {&pts, &kb}, p);
  d->finish();
  EXPECT_EQ(d->take_timings().size(), 2u);
}

MV_INSTANTIATE_ON_ALL_DEVICES(RuntimeTest);

}  // namespace
}  // namespace mv::test

// The C API's codes, one per kind of failure, each met through the API: a bad argument, malformed input, a file
// the system refuses, a memory budget too small, a cancel; a device's and an internal failure through the guard
// every entry point runs in (no public call can make a healthy device fail). Messages speak the library's
// terms, never the CLI's flags.
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "handles.h"
#include "megavox/megavox.hpp"
#include "capi_fixture.h"
#include "test_support.h"

namespace mv::test::capi {
namespace {

class CApiErrorsTest : public ::testing::TestWithParam<DeviceInfo> {};

struct Recorded {
  MvError code = MV_ERROR_NONE;
  std::string message;
};
void record_into(void* user, MvError code, const char* message) {
  *static_cast<Recorded*>(user) = {code, message};
}

TEST(CApiErrorCodes, EveryCodeHasItsName) {
  const std::pair<MvError, const char*> names[] = {
      {MV_ERROR_NONE, "MV_ERROR_NONE"},
      {MV_ERROR_UNKNOWN, "MV_ERROR_UNKNOWN"},
      {MV_ERROR_INVALID_ARGUMENT, "MV_ERROR_INVALID_ARGUMENT"},
      {MV_ERROR_INVALID_OPERATION, "MV_ERROR_INVALID_OPERATION"},
      {MV_ERROR_OUT_OF_MEMORY, "MV_ERROR_OUT_OF_MEMORY"},
      {MV_ERROR_UNSUPPORTED_DEVICE, "MV_ERROR_UNSUPPORTED_DEVICE"},
      {MV_ERROR_CANCELLED, "MV_ERROR_CANCELLED"},
      {MV_ERROR_INPUT, "MV_ERROR_INPUT"},
      {MV_ERROR_IO, "MV_ERROR_IO"},
      {MV_ERROR_DEVICE, "MV_ERROR_DEVICE"}};
  for (const auto& [code, name] : names) EXPECT_STREQ(mvGetErrorString(code), name);
  EXPECT_EQ(MV_ERROR_INPUT, 7);  // the codes already published keep their values
  EXPECT_EQ(MV_ERROR_IO, 8);
  EXPECT_EQ(MV_ERROR_DEVICE, 9);
}

TEST_P(CApiErrorsTest, EachKindOfFailureHasItsCode) {
  CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  Recorded seen;
  mvSetDeviceErrorFunction(dev.handle, record_into, &seen);
  const Mesh m = octahedron();
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.resolution = 16;

  // input: arrays that are no mesh
  std::vector<uint32_t> bad = m.indices;
  bad[0] = 99;
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, bad.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_INPUT) << seen.message;
  const std::string garbage = temp_path("capi_errors_garbage.mvx");
  write_bytes(garbage, {'n', 'o', 't', ' ', 'm', 'v', 'x'});
  EXPECT_EQ(mvOpenScene(dev.handle, garbage.c_str()), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_INPUT) << seen.message;

  // I/O: a file that is not there, an output folder that is not there
  EXPECT_EQ(mvBuildSceneFromFile(dev.handle, "/no/such/mesh.obj", &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_IO) << seen.message;
  a.output = "/no/such/folder/out.mvx";
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_IO) << seen.message;
  a.output = nullptr;

  // invalid argument: a setting out of range, in the library's words
  a.resolution = 48;
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_INVALID_ARGUMENT) << seen.message;
  a.resolution = 16;
  a.voxelize = "fat";
  EXPECT_EQ(mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  EXPECT_EQ(seen.code, MV_ERROR_INVALID_ARGUMENT) << seen.message;
  EXPECT_NE(seen.message.find("voxelization rule 'fat'"), std::string::npos) << seen.message;
  a.voxelize = nullptr;

  // the device's failure and an internal one, as the guard of every entry point sorts them
  EXPECT_EQ(guard(dev.handle, [] { throw DeviceError("OpenCL: clEnqueueNDRangeKernel failed (CL_OUT_OF_RESOURCES)"); }),
            MV_ERROR_DEVICE);
  EXPECT_EQ(seen.code, MV_ERROR_DEVICE);
  EXPECT_EQ(mvGetDeviceError(dev.handle), MV_ERROR_DEVICE);
  EXPECT_EQ(guard(dev.handle, [] { throw std::logic_error("a broken invariant"); }), MV_ERROR_UNKNOWN);
  EXPECT_EQ(seen.code, MV_ERROR_UNKNOWN);
  EXPECT_EQ(guard(dev.handle, [] { throw IoError("cannot write 'x': No space left on device"); }), MV_ERROR_IO);
  EXPECT_EQ(guard(dev.handle, [] { throw std::bad_alloc(); }), MV_ERROR_OUT_OF_MEMORY);
  EXPECT_EQ(seen.message, "out of host memory");
}

TEST_P(CApiErrorsTest, BudgetsTooSmallAreOutOfMemoryInTheLibrarysTerms) {
  // a device budget far below a 512^3 in-core build's voxels
  CDevice small(GetParam(), "memory=1M");
  ASSERT_TRUE(small.handle);
  const Mesh m = octahedron();
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.resolution = 512;
  a.cube = MV_CUBE_IN_CORE;
  EXPECT_EQ(mvBuildSceneFromMemory(small.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  std::string message = mvGetDeviceLastErrorMessage(small.handle);
  EXPECT_EQ(mvGetDeviceError(small.handle), MV_ERROR_OUT_OF_MEMORY) << message;
  EXPECT_NE(message.find("device memory budget"), std::string::npos) << message;
  EXPECT_EQ(message.find("--"), std::string::npos) << message;

  // a host budget below what the cubes' table alone needs
  CDevice host(GetParam(), "host_memory=64K");
  ASSERT_TRUE(host.handle);
  a.resolution = 1u << 21;
  a.cube = 8;
  EXPECT_EQ(mvBuildSceneFromMemory(host.handle, m.positions.data(), 6, m.indices.data(), 8, &a), nullptr);
  message = mvGetDeviceLastErrorMessage(host.handle);
  EXPECT_EQ(mvGetDeviceError(host.handle), MV_ERROR_OUT_OF_MEMORY) << message;
  EXPECT_NE(message.find("host memory budget"), std::string::npos) << message;
  EXPECT_EQ(message.find("--"), std::string::npos) << message;

  // a budget above what the device has is a bad argument of mvNewDevice
  EXPECT_EQ(mvNewDevice(("device=" + GetParam().selector() + ",memory=1000000G").c_str()), nullptr);
  message = mvGetDeviceLastErrorMessage(nullptr);
  EXPECT_EQ(mvGetDeviceError(nullptr), MV_ERROR_INVALID_ARGUMENT) << message;
  EXPECT_NE(message.find("the device memory budget"), std::string::npos) << message;

  // the RAII layer carries the code
  megavox::Device cpp("device=" + GetParam().selector() + ",memory=1M");
  try {
    a.resolution = 512;
    a.cube = MV_CUBE_IN_CORE;
    cpp.build(m.positions, m.indices, &a);
    ADD_FAILURE() << "no exception";
  } catch (const megavox::Error& e) {
    EXPECT_EQ(e.code(), MV_ERROR_OUT_OF_MEMORY) << e.what();
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(CApiErrorsTest);

}  // namespace
}  // namespace mv::test::capi

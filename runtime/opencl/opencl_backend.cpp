// Backend over OpenCL 1.2 (PoCL on the CPU here; any ICD elsewhere).
// One in-order queue per device, so barrier() has nothing to do: each command starts after the previous
// one ends. Programs are built once per device and cached by their .cl path; kernels by entry name. A program
// compiled once is kept in the kernel cache (kernel_cache.h) as the driver's binary and loaded from there later.
#define CL_TARGET_OPENCL_VERSION 120
#define CL_USE_DEPRECATED_OPENCL_1_2_APIS
#include <CL/cl.h>

#include <deque>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "backend.h"
#include "huge_pages.h"
#include "kernel_cache.h"
#include "megavox/error.h"

namespace mv::rt {
namespace {

std::string cl_error_name(cl_int err) {
  switch (err) {
#define MV_CL_CASE(e) \
  case e:             \
    return #e;
    MV_CL_CASE(CL_DEVICE_NOT_FOUND) MV_CL_CASE(CL_DEVICE_NOT_AVAILABLE) MV_CL_CASE(CL_COMPILER_NOT_AVAILABLE)
    MV_CL_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE) MV_CL_CASE(CL_OUT_OF_RESOURCES) MV_CL_CASE(CL_OUT_OF_HOST_MEMORY)
    MV_CL_CASE(CL_BUILD_PROGRAM_FAILURE) MV_CL_CASE(CL_MISALIGNED_SUB_BUFFER_OFFSET) MV_CL_CASE(CL_INVALID_VALUE)
    MV_CL_CASE(CL_INVALID_DEVICE) MV_CL_CASE(CL_INVALID_CONTEXT) MV_CL_CASE(CL_INVALID_MEM_OBJECT)
    MV_CL_CASE(CL_INVALID_BUFFER_SIZE) MV_CL_CASE(CL_INVALID_PROGRAM) MV_CL_CASE(CL_INVALID_KERNEL_NAME)
    MV_CL_CASE(CL_INVALID_KERNEL) MV_CL_CASE(CL_INVALID_ARG_INDEX) MV_CL_CASE(CL_INVALID_ARG_VALUE)
    MV_CL_CASE(CL_INVALID_ARG_SIZE) MV_CL_CASE(CL_INVALID_KERNEL_ARGS) MV_CL_CASE(CL_INVALID_WORK_GROUP_SIZE)
    MV_CL_CASE(CL_INVALID_WORK_ITEM_SIZE) MV_CL_CASE(CL_INVALID_GLOBAL_WORK_SIZE) MV_CL_CASE(CL_INVALID_OPERATION)
#undef MV_CL_CASE
    default:
      return "OpenCL error " + std::to_string(err);
  }
}

void check(cl_int err, const std::string& what) {
  if (err != CL_SUCCESS) throw DeviceError("OpenCL: " + what + " failed (" + cl_error_name(err) + ")");
}

template <class T>
T device_value(cl_device_id dev, cl_device_info param) {
  T value{};
  clGetDeviceInfo(dev, param, sizeof(T), &value, nullptr);
  return value;
}

std::string device_string(cl_device_id dev, cl_device_info param) {
  size_t size = 0;
  if (clGetDeviceInfo(dev, param, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string s(size, '\0');
  clGetDeviceInfo(dev, param, size, s.data(), nullptr);
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

std::string platform_string(cl_platform_id p, cl_platform_info param) {
  size_t size = 0;
  if (clGetPlatformInfo(p, param, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string s(size, '\0');
  clGetPlatformInfo(p, param, size, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

constexpr const char* kBuildOptions = "-cl-std=CL1.2";

struct ClDevice {
  cl_platform_id platform;
  cl_device_id device;
};

// All devices of all platforms, in enumeration order: the meaning of "ocl:N".
std::vector<ClDevice> all_devices() {
  cl_uint nplat = 0;
  if (clGetPlatformIDs(0, nullptr, &nplat) != CL_SUCCESS || nplat == 0) return {};
  std::vector<cl_platform_id> plats(nplat);
  clGetPlatformIDs(nplat, plats.data(), nullptr);
  std::vector<ClDevice> out;
  for (cl_platform_id p : plats) {
    cl_uint ndev = 0;
    if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &ndev) != CL_SUCCESS || ndev == 0) continue;
    std::vector<cl_device_id> devs(ndev);
    clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, ndev, devs.data(), nullptr);
    for (cl_device_id d : devs) out.push_back({p, d});
  }
  return out;
}

DeviceInfo describe(const ClDevice& d, int index) {
  DeviceInfo info;
  info.backend = "opencl";
  info.index = index;
  info.name = device_string(d.device, CL_DEVICE_NAME);
  info.platform = platform_string(d.platform, CL_PLATFORM_NAME);
  info.vendor = platform_string(d.platform, CL_PLATFORM_VENDOR);
  info.driver = device_string(d.device, CL_DRIVER_VERSION);
  info.api_version = device_string(d.device, CL_DEVICE_VERSION);
  auto type = device_value<cl_device_type>(d.device, CL_DEVICE_TYPE);
  info.type = (type & CL_DEVICE_TYPE_GPU) ? "gpu" : (type & CL_DEVICE_TYPE_CPU) ? "cpu" : "other";
  info.compute_units = device_value<cl_uint>(d.device, CL_DEVICE_MAX_COMPUTE_UNITS);
  info.global_memory_bytes = device_value<cl_ulong>(d.device, CL_DEVICE_GLOBAL_MEM_SIZE);
  info.max_allocation_bytes = device_value<cl_ulong>(d.device, CL_DEVICE_MAX_MEM_ALLOC_SIZE);
  info.max_binding_bytes = info.max_allocation_bytes;
  info.local_memory_bytes = device_value<cl_ulong>(d.device, CL_DEVICE_LOCAL_MEM_SIZE);
  info.max_work_group_size = static_cast<uint32_t>(device_value<size_t>(d.device, CL_DEVICE_MAX_WORK_GROUP_SIZE));
  info.max_groups = 0x7fffffff;  // OpenCL bounds the global size only by size_t
  info.max_groups_y = 0x7fffffff;
  info.subgroup_size = 0;
  info.fp64 = device_value<cl_device_fp_config>(d.device, CL_DEVICE_DOUBLE_FP_CONFIG) != 0;
  info.int64 = true;  // 64-bit integers are core OpenCL C
  // cl_khr_int64_*_atomics cover __global and __local alike; both halves give add, min, max, or, xchg, cmpxchg.
  const std::string extensions = " " + device_string(d.device, CL_DEVICE_EXTENSIONS) + " ";
  info.atomics64 = extensions.find(" cl_khr_int64_base_atomics ") != std::string::npos &&
                   extensions.find(" cl_khr_int64_extended_atomics ") != std::string::npos;
  info.shared_atomics64 = info.atomics64;
  const cl_uint int_lanes = device_value<cl_uint>(d.device, CL_DEVICE_NATIVE_VECTOR_WIDTH_INT);
  info.simd_width = info.type == "gpu" ? 32 : std::max<cl_uint>(1, int_lanes);
  apply_kernel_shape(info, KernelShape::automatic);
  return info;
}

struct ClArena final : BackendArena {
  cl_mem mem = nullptr;
  std::unique_ptr<HugeBlock> storage;  // ours, where the device computes in host memory
  ~ClArena() override {
    if (mem) clReleaseMemObject(mem);  // before the storage it may use
  }
};

struct ClBuffer final : BackendBuffer {
  cl_mem mem = nullptr;  // a sub-buffer of the arena
  const void* host = nullptr;  // its storage, where the arena's is host memory of ours
  ~ClBuffer() override {
    if (mem) clReleaseMemObject(mem);
  }
};

struct ClKernel final : BackendKernel {
  std::string name;
  cl_kernel kernel = nullptr;
  ~ClKernel() override {
    if (kernel) clReleaseKernel(kernel);
  }
};

class OpenCLBackend final : public Backend {
 public:
  OpenCLBackend(const ClDevice& d, int index, const std::string& kernel_cache)
      : device_(d.device),
        info_(describe(d, index)),
        cache_(kernel_cache),
        host_unified_(info_.type == "cpu" && device_value<cl_bool>(d.device, CL_DEVICE_HOST_UNIFIED_MEMORY)) {
    cl_int err = CL_SUCCESS;
    context_ = clCreateContext(nullptr, 1, &device_, nullptr, nullptr, &err);
    check(err, "creating a context on '" + info_.name + "'");
    queue_ = clCreateCommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE, &err);
    check(err, "creating a command queue on '" + info_.name + "'");
  }

  ~OpenCLBackend() override {
    if (queue_) clFinish(queue_);
    for (auto& t : pending_) clReleaseEvent(t.event);
    for (auto& m : marks_) clReleaseEvent(m.event);
    kernels_.clear();
    for (auto& [name, prog] : programs_) clReleaseProgram(prog);
    if (queue_) clReleaseCommandQueue(queue_);
    if (context_) clReleaseContext(context_);
  }

  const DeviceInfo& info() const override { return info_; }

  std::unique_ptr<BackendArena> create_arena(uint64_t bytes) override {
    auto arena = std::make_unique<ClArena>();
    cl_int err = CL_SUCCESS;
    if (host_unified_) {
      // A CPU device's memory is host memory that the driver would take in 4 KiB pages, whose first touch costs
      // a fault each (0.4 GB/s on the 2-core VMs measured here, 18 GB/s on huge pages): the arena uses storage
      // of ours on huge pages instead, which the driver computes in place (CL_MEM_USE_HOST_PTR).
      arena->storage = std::make_unique<HugeBlock>(bytes);
      arena->mem = clCreateBuffer(context_, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes, arena->storage->data(), &err);
      arena->host = arena->storage->data();
    } else {
      arena->mem = clCreateBuffer(context_, CL_MEM_READ_WRITE, bytes, nullptr, &err);
    }
    check(err, "allocating " + std::to_string(bytes) + " bytes of device memory");
    return arena;
  }

  std::unique_ptr<BackendBuffer> create_buffer(BackendArena& arena, uint64_t offset, uint64_t bytes) override {
    auto buf = std::make_unique<ClBuffer>();
    cl_buffer_region region{offset, bytes};
    cl_int err = CL_SUCCESS;
    buf->mem = clCreateSubBuffer(static_cast<ClArena&>(arena).mem, CL_MEM_READ_WRITE,
                                 CL_BUFFER_CREATE_TYPE_REGION, &region, &err);
    check(err, "creating a sub-buffer at offset " + std::to_string(offset));
    if (arena.host) buf->host = static_cast<const char*>(arena.host) + offset;
    return buf;
  }

  // CL_MEM_USE_HOST_PTR storage that a CPU device computes in: after finish() it holds what the kernels wrote.
  const void* host_pointer(BackendBuffer& buffer) const override { return static_cast<ClBuffer&>(buffer).host; }

  void upload(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) override {
    if (bytes == 0) return;
    Blocking blocked(*this);
    check(clEnqueueWriteBuffer(queue_, mem(dst), CL_TRUE, offset, bytes, src, 0, nullptr, nullptr), "upload");
  }

  void upload_async(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) override {
    if (bytes == 0) return;
    check(clEnqueueWriteBuffer(queue_, mem(dst), CL_FALSE, offset, bytes, src, 0, nullptr, nullptr), "upload");
  }

  void download(BackendBuffer& src, uint64_t offset, void* dst, uint64_t bytes) override {
    if (bytes == 0) return;
    Blocking blocked(*this);
    check(clEnqueueReadBuffer(queue_, mem(src), CL_TRUE, offset, bytes, dst, 0, nullptr, nullptr), "download");
  }

  void fill(BackendBuffer& dst, uint64_t offset, uint64_t bytes, uint32_t pattern) override {
    if (bytes == 0) return;
    check(clEnqueueFillBuffer(queue_, mem(dst), &pattern, sizeof pattern, offset, bytes, 0, nullptr, nullptr),
          "fill");
  }

  void copy(BackendBuffer& src, uint64_t src_offset, BackendBuffer& dst, uint64_t dst_offset,
            uint64_t bytes) override {
    if (bytes == 0) return;
    check(clEnqueueCopyBuffer(queue_, mem(src), mem(dst), src_offset, dst_offset, bytes, 0, nullptr, nullptr),
          "copy");
  }

  BackendKernel& kernel(const KernelDesc& desc) override {
    if (auto it = kernels_.find(desc.name); it != kernels_.end()) return *it->second;
    cl_program program = build_program(desc);
    auto k = std::make_unique<ClKernel>();
    k->name = desc.name;
    cl_int err = CL_SUCCESS;
    k->kernel = clCreateKernel(program, desc.name.c_str(), &err);
    check(err, "creating kernel '" + desc.name + "' from program '" + desc.cl_program + "'");
    if (desc.declared_args >= 0) {  // the source agrees with kernels/kernels.cmake: its buffers, then one struct
      cl_uint args = 0;
      check(clGetKernelInfo(k->kernel, CL_KERNEL_NUM_ARGS, sizeof(args), &args, nullptr),
            "reading the arguments of '" + desc.name + "'");
      if (args != static_cast<cl_uint>(desc.declared_args))
        throw Error("kernel '" + desc.name + "' takes " + std::to_string(args) + " arguments in " + desc.cl_program +
                    ", but kernels/kernels.cmake declares " + std::to_string(desc.declared_args - 1) +
                    " buffers and a parameter struct");
    }
    return *kernels_.emplace(desc.name, std::move(k)).first->second;
  }

  void dispatch(BackendKernel& kernel, const LaunchGrid& grid, std::span<BackendBuffer* const> buffers,
                const void* params, size_t params_bytes) override {
    if (grid.groups[0] == 0 || grid.groups[1] == 0) return;
    auto& k = static_cast<ClKernel&>(kernel);
    cl_uint arg = 0;
    for (BackendBuffer* b : buffers) {
      cl_mem m = b ? static_cast<ClBuffer*>(b)->mem : nullptr;
      check(clSetKernelArg(k.kernel, arg++, sizeof(cl_mem), &m), "setting buffer arguments of '" + k.name + "'");
    }
    if (params_bytes > 0)
      check(clSetKernelArg(k.kernel, arg, params_bytes, params), "setting the parameters of '" + k.name + "'");
    const size_t local[2] = {grid.local[0], grid.local[1]};
    const size_t global[2] = {size_t{grid.groups[0]} * grid.local[0], size_t{grid.groups[1]} * grid.local[1]};
    const cl_uint dims = grid.groups[1] > 1 || grid.local[1] > 1 ? 2 : 1;
    cl_event event = nullptr;
    check(clEnqueueNDRangeKernel(queue_, k.kernel, dims, nullptr, global, local, 0, nullptr,
                                 profiling_ ? &event : nullptr),
          "launching '" + k.name + "'");
    if (event) pending_.push_back({k.name, event, uint64_t{global[0]} * global[1]});
  }

  void barrier() override {}  // the queue is in order

  // A mark is a marker event after the work recorded so far; clFlush starts that work without waiting for it.
  uint64_t submit() override {
    cl_event event = nullptr;
    check(clEnqueueMarkerWithWaitList(queue_, 0, nullptr, &event), "marking the stream");
    marks_.push_back({++last_mark_, event});
    check(clFlush(queue_), "starting the device's work");
    return last_mark_;
  }

  void wait(uint64_t mark) override {
    if (mark > last_mark_) throw Error("wait for stream mark " + std::to_string(mark) + ", which was never made");
    auto done = marks_.begin();
    while (done != marks_.end() && done->mark <= mark) ++done;
    if (done == marks_.begin()) return;  // already waited for
    cl_event last = std::prev(done)->event;
    Blocking blocked(*this);
    const cl_int err = clWaitForEvents(1, &last);  // the queue is in order: the earlier marks are done too
    for (auto m = marks_.begin(); m != done; ++m) clReleaseEvent(m->event);
    marks_.erase(marks_.begin(), done);
    check(err, "waiting for the device");
  }

  void finish() override {
    Blocking blocked(*this);
    check(clFinish(queue_), "waiting for the device");
    for (auto& m : marks_) clReleaseEvent(m.event);
    marks_.clear();
    for (auto& t : pending_) {
      cl_ulong start = 0, end = 0;
      clGetEventProfilingInfo(t.event, CL_PROFILING_COMMAND_START, sizeof start, &start, nullptr);
      clGetEventProfilingInfo(t.event, CL_PROFILING_COMMAND_END, sizeof end, &end, nullptr);
      timings_.push_back({t.kernel, end > start ? end - start : 0, t.work_items});
      clReleaseEvent(t.event);
    }
    pending_.clear();
  }

  void set_profiling(bool on) override { profiling_ = on; }
  std::vector<KernelTiming> take_timings() override { return std::exchange(timings_, {}); }

 private:
  static cl_mem mem(BackendBuffer& b) { return static_cast<ClBuffer&>(b).mem; }

  // The driver's binary is keyed by everything that shapes it: the source, the options, the device and driver.
  std::string cache_key(const KernelDesc& desc) const {
    return KernelCache::key({desc.cl_source ? desc.cl_source : "", kBuildOptions, info_.name, info_.platform,
                             info_.driver, info_.api_version});
  }

  cl_program build_program(const KernelDesc& desc) {
    if (auto it = programs_.find(desc.cl_program); it != programs_.end()) return it->second;
    if (!desc.cl_source) throw Error("OpenCL: kernel '" + desc.name + "' has no OpenCL source");
    const std::string key = cache_key(desc);
    cl_program program = nullptr;
    if (auto binary = cache_.load(key)) program = program_from_binary(*binary);
    if (!program) {
      program = announced_compile(desc.cl_program, [&] { return compile(desc); });
      cache_.store(key, binary_of(program));
    }
    programs_.emplace(desc.cl_program, program);
    return program;
  }

  cl_program compile(const KernelDesc& desc) {
    cl_int err = CL_SUCCESS;
    const char* src = desc.cl_source;
    cl_program program = clCreateProgramWithSource(context_, 1, &src, nullptr, &err);
    check(err, "creating program '" + desc.cl_program + "'");
    err = clBuildProgram(program, 1, &device_, kBuildOptions, nullptr, nullptr);
    if (err != CL_SUCCESS) {
      std::string log = build_log(program);
      clReleaseProgram(program);
      throw DeviceError("OpenCL: building program '" + desc.cl_program + "' (kernel '" + desc.name + "') for '" +
                  info_.name + "' failed (" + cl_error_name(err) + "). Compiler log:\n" + log);
    }
    return program;
  }

  // nullptr when the driver rejects the bytes (a torn file, another driver's): the caller compiles instead.
  cl_program program_from_binary(const std::string& binary) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(binary.data());
    const size_t size = binary.size();
    cl_int status = CL_SUCCESS, err = CL_SUCCESS;
    cl_program program = clCreateProgramWithBinary(context_, 1, &device_, &size, &bytes, &status, &err);
    if (err != CL_SUCCESS || status != CL_SUCCESS) {
      if (program) clReleaseProgram(program);
      return nullptr;
    }
    if (clBuildProgram(program, 1, &device_, kBuildOptions, nullptr, nullptr) != CL_SUCCESS) {
      clReleaseProgram(program);
      return nullptr;
    }
    return program;
  }

  // Empty when the driver gives none: that program is then compiled again by the next run.
  std::string binary_of(cl_program program) {
    size_t size = 0;
    if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, nullptr) != CL_SUCCESS || !size)
      return {};
    std::string binary(size, '\0');
    unsigned char* out = reinterpret_cast<unsigned char*>(binary.data());
    if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof out, &out, nullptr) != CL_SUCCESS) return {};
    return binary;
  }

  std::string build_log(cl_program program) {
    size_t size = 0;
    clGetProgramBuildInfo(program, device_, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
    std::string log(size, '\0');
    if (size) clGetProgramBuildInfo(program, device_, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return log.empty() ? "(empty)" : log;
  }

  struct PendingTiming {
    std::string kernel;
    cl_event event;
    uint64_t work_items;
  };
  struct Mark {
    uint64_t mark;
    cl_event event;
  };

  cl_device_id device_;
  DeviceInfo info_;
  KernelCache cache_;
  bool host_unified_ = false;  // a CPU device computing in host memory: arenas on storage of ours
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
  std::map<std::string, cl_program> programs_;
  std::map<std::string, std::unique_ptr<ClKernel>> kernels_;
  bool profiling_ = false;
  std::vector<PendingTiming> pending_;
  std::deque<Mark> marks_;  // submitted and not yet waited for, oldest first
  uint64_t last_mark_ = 0;
  std::vector<KernelTiming> timings_;
};

}  // namespace

std::vector<DeviceInfo> enumerate_opencl() {
  std::vector<DeviceInfo> out;
  auto devs = all_devices();
  for (size_t i = 0; i < devs.size(); ++i) out.push_back(describe(devs[i], static_cast<int>(i)));
  return out;
}

std::unique_ptr<Backend> open_opencl(int index, const std::string& kernel_cache) {
  auto devs = all_devices();
  if (index < 0 || static_cast<size_t>(index) >= devs.size())
    throw Error("OpenCL: no device ocl:" + std::to_string(index) + " (" + std::to_string(devs.size()) + " found)");
  return std::make_unique<OpenCLBackend>(devs[index], index, kernel_cache);
}

}  // namespace mv::rt

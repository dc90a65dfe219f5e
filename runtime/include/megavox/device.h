// megavox — compute devices, device memory and kernel dispatch, independent of the backend API.
//
// A Device is one OpenCL or Vulkan device opened with a memory budget. Device memory comes only from its
// page pool (fixed-size pages carved out of a few large allocations); a request the budget cannot hold
// throws mv::Error naming what was asked and what is left. Work is recorded in one ordered stream:
// dispatch/fill/copy may overlap until barrier(); submit() starts what is recorded and wait() waits for a
// point of it; finish() waits for everything; upload/download wait for earlier work first.
#pragma once
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeinfo>
#include <vector>

#include "megavox/kernel_ids.h"  // generated from kernels/kernels.cmake

namespace mv {

namespace rt {
class Backend;
class BackendBuffer;
class BackendKernel;
class MemoryPool;
struct EmbeddedKernel;
struct KernelDesc;
}  // namespace rt

struct DeviceInfo {
  std::string backend;   // "opencl" or "vulkan"
  int index = 0;         // position among the backend's devices: selector "ocl:N" / "vk:N"
  std::string name;      // device name as the driver reports it
  std::string platform;  // OpenCL platform name; Vulkan: driver name
  std::string vendor;    // OpenCL platform vendor ("The pocl project"); Vulkan: driver name
  std::string driver;    // driver version
  std::string api_version;
  std::string type;      // "cpu", "gpu" or "other"
  uint32_t compute_units = 0;
  uint64_t global_memory_bytes = 0;
  uint64_t max_allocation_bytes = 0;
  uint64_t max_binding_bytes = 0;  // largest single buffer binding (Vulkan storage range; OpenCL: max alloc)
  uint64_t local_memory_bytes = 0;
  uint32_t max_work_group_size = 0;
  uint32_t max_groups = 0;         // largest group count along x of a dispatch
  uint32_t max_groups_y = 0;       // ... along y
  uint32_t subgroup_size = 0;      // 0 when the API does not say
  bool fp64 = false;
  bool int64 = false;
  // Most iterations one loop statement may run in one work-item, summed over every time the loop is entered;
  // 0 = no limit. llvmpipe (lavapipe) silently ends a shader loop once it has run 65535 iterations in the
  // invocation, so block-per-work-item kernels keep their blocks (and nested loops) below that.
  uint32_t max_loop_iterations = 0;
  // Kernel-language features beyond the base every kernel uses (32-bit atomics, shared memory, barriers):
  bool atomics64 = false;         // 64-bit atomics on global memory
  bool shared_atomics64 = false;  // 64-bit atomics on work-group shared memory
  // How to shape launches, filled by the backend (host code reads these, never backend or type names):
  bool massively_parallel = false;         // a GPU: thousands of work-items in flight; else a few CPU threads,
                                           // each best on a contiguous block of items
  uint32_t simd_width = 1;                 // work-items run in lock step: Vulkan's subgroup size (lavapipe 8);
                                           // OpenCL CPUs their native int vector width; OpenCL GPUs 32 (unsaid)
  uint32_t preferred_work_group_size = 1;  // for block-per-work-item and grid-stride kernels: GPUs 64, lavapipe
                                           // its SIMD width, PoCL 1 (it runs a work-group's items as a loop)
  bool cheap_parameter_loads = true;       // a uniform value read from device memory costs about one load; false
                                           // on lavapipe, which runs each global load as a loop over the lanes

  std::string selector() const { return (backend == "opencl" ? "ocl:" : "vk:") + std::to_string(index); }
};

// The work-group grid of one dispatch: groups[d] work-groups of local[d] work-items along x (0) and y (1).
// 1-D dispatches leave y at 1; 2-D ones cover image grids (MV_GLOBAL_ID_D(1) in kernels).
struct LaunchGrid {
  uint32_t groups[2] = {1, 1};
  uint32_t local[2] = {1, 1};
};

struct KernelTiming {
  std::string kernel;
  uint64_t ns = 0;          // execution time from the device's timestamps
  uint64_t work_items = 0;  // the dispatch's work-items: groups x local size, both axes
};

// How host code shapes launches (DeviceInfo::massively_parallel, preferred_work_group_size): `automatic` by the
// device's type, `gpu` as on a GPU (wide grids, cooperative variants, work-groups of 64), `cpu` as on a few CPU
// threads (a contiguous block per work-item). Every shape gives the same bytes; forcing one shows how the other
// runs on the device at hand (`--kernel-shape`, $MEGAVOX_KERNEL_SHAPE).
enum class KernelShape { automatic, gpu, cpu };
// "auto", "gpu", "cpu"; throws mv::CodedError (invalid_argument) naming the choices for anything else.
KernelShape parse_kernel_shape(std::string_view text);
const char* kernel_shape_name(KernelShape shape);
// Sets the launch fields of `info` for `shape` (automatic: by info.type). simd_width is the device's own and
// stays: Vulkan's real subgroup size, never assumed.
void apply_kernel_shape(DeviceInfo& info, KernelShape shape);

// Every device both backends can see: OpenCL devices first (all platforms, enumeration order), then Vulkan.
std::vector<DeviceInfo> list_devices();

// Resolves a selector: "ocl:N", "vk:N", or a case-insensitive substring of a device name, platform name or
// platform vendor (so "pocl" finds PoCL, whose platform is "Portable Computing Language").
// Empty means the default: the first GPU (Vulkan before OpenCL when a GPU is visible through both), else
// the first OpenCL CPU device (PoCL), else the first device. Throws mv::Error listing the devices when
// nothing matches.
DeviceInfo select_device(const std::string& selector);

// Parses sizes such as "512M", "2G", "16K", "1048576" (binary units). Throws mv::Error on garbage.
uint64_t parse_size(std::string_view text);
std::string format_bytes(uint64_t bytes);

class Device;

// Device memory owned by a Device's page pool. Move-only; returns its pages when destroyed.
class Buffer {
 public:
  Buffer() = default;
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer();

  uint64_t bytes() const { return bytes_; }
  bool empty() const { return bytes_ == 0; }

 private:
  friend class Device;
  void release();
  rt::MemoryPool* pool_ = nullptr;
  uint32_t arena_ = 0;
  uint64_t first_page_ = 0;
  uint64_t pages_ = 0;
  uint64_t bytes_ = 0;
  struct ImplDeleter {
    void operator()(rt::BackendBuffer* b) const;  // out of line: the type is the backend's
  };
  std::unique_ptr<rt::BackendBuffer, ImplDeleter> impl_;
};

// A built kernel; owned by its Device, valid while the Device lives. Embedded kernels carry the signature
// kernels/kernels.cmake declares (buffer count, parameter struct), and every dispatch is checked against it.
class Kernel {
 public:
  const std::string& name() const { return name_; }

 private:
  friend class Device;
  std::string name_;
  rt::BackendKernel* impl_ = nullptr;
  bool checked_ = false;  // false for kernels built from explicit sources (runtime tests)
  uint32_t buffers_ = 0;
  const std::type_info* params_type_ = nullptr;
  size_t params_bytes_ = 0;
  const char* params_name_ = "";
};

// A kernel compile that the kernel cache could not spare: a program's first use on a device and driver (later
// runs load it from the cache in milliseconds). Reported, never printed by the runtime, which also serves the C
// API and the service; the CLI turns it into a notice and a progress line on a terminal.
struct CompileEvent {
  std::string device;   // the device's name
  std::string program;  // what compiles: an OpenCL program's .cl path, a Vulkan kernel and its work-group size
  uint32_t count = 0;   // programs this Device has compiled, this one included (1: the first)
  bool done = false;    // false just before the compile starts, true once it has ended
};
using CompileListener = std::function<void(const CompileEvent&)>;

struct DeviceOptions {
  std::string selector;         // see select_device(); empty = default (or $MEGAVOX_DEVICE when set)
  uint64_t memory_budget = 0;   // 0 = default: a safe fraction of what the device reports
  bool profile = false;         // collect per-dispatch timings (take_timings)
  // automatic = $MEGAVOX_KERNEL_SHAPE when set, else by the device's type; info() reports the effective shape.
  KernelShape kernel_shape = KernelShape::automatic;
  // Folder of compiled OpenCL programs, and of records of the Vulkan pipelines the driver has compiled (it keeps
  // their code in its own cache); empty = $MEGAVOX_KERNEL_CACHE, else $XDG_CACHE_HOME/megavox/kernels, else
  // ~/.cache/megavox/kernels.
  std::string kernel_cache;
  // Called before and after each compile the cache could not spare, from the thread that caused it: an OpenCL
  // program when one of its kernels is first asked for, a Vulkan pipeline at its first dispatch. Compiles happen
  // as they are needed, so how many a command makes is not known up front: compiling every program at once to
  // know it took 100 s instead of 26 s for a 64^3 build on PoCL.
  CompileListener on_compile;
  // The default memory budget divided among this many processes (the ranks of an MPI run on one node).
  uint32_t budget_share = 1;
};

class Device {
 public:
  static std::unique_ptr<Device> open(const DeviceOptions& options = {});
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const DeviceInfo& info() const;
  uint64_t memory_budget() const;
  uint64_t memory_used() const;  // bytes in pages handed out
  // The most memory_used() has been since reset_memory_peak() (or since the device opened): what a sequence of
  // calls held on the device at most, retired buffers not yet reclaimed included.
  uint64_t memory_peak() const;
  void reset_memory_peak();
  uint64_t page_bytes() const;

  // Throws mv::Error when the budget or the largest single allocation cannot hold `bytes`.
  Buffer alloc(uint64_t bytes, std::string_view what);

  void upload(Buffer& dst, const void* src, uint64_t bytes, uint64_t offset = 0);
  void download(const Buffer& src, void* dst, uint64_t bytes, uint64_t offset = 0) const;
  // An upload recorded in the stream like copy(): returns at once, runs in order with the other commands
  // (barrier() before a dispatch that reads it) and no later than finish(); `src` must stay unchanged until
  // finish(). The host goes on while it runs (OpenCL: a non-blocking write; Vulkan: staged now, copied then).
  void upload_async(Buffer& dst, const void* src, uint64_t bytes, uint64_t offset = 0);
  void fill(Buffer& dst, uint32_t pattern, uint64_t bytes, uint64_t offset = 0);
  // Where the device computes in host memory (CPU devices: PoCL, lavapipe), the buffer's bytes as the host sees
  // them, read in place instead of downloaded: valid while the buffer lives, and what the device wrote once
  // finish() (or the wait() for a mark after the writes) has returned. nullptr on other devices (download instead).
  const void* host_view(const Buffer& buffer) const;
  void copy(const Buffer& src, Buffer& dst, uint64_t bytes, uint64_t src_offset = 0, uint64_t dst_offset = 0);

  // Kernels embedded at build time (kernels/kernels.cmake); built on first use, once per Device.
  Kernel& kernel(KernelId id);
  // A kernel of another embedded table (the tests' own: tests/kernels/kernels.cmake), built and checked alike.
  Kernel& kernel(const rt::EmbeddedKernel& entry);

  // Records a dispatch of `groups` work-groups of `local_size` items. Kernel arguments: the buffers in
  // order, then `params` (a trivially copyable struct from kernels/common, shared with the kernel source).
  // Throws mv::Error naming the kernel when the buffer count or the parameter type differs from its
  // declaration in kernels/kernels.cmake.
  template <class Params>
  void dispatch(Kernel& k, uint32_t groups, uint32_t local_size, std::initializer_list<const Buffer*> buffers,
                const Params& params) {
    dispatch(k, LaunchGrid{{groups, 1}, {local_size, 1}}, buffers, params);
  }
  // The same over a 2-D grid of work-groups.
  template <class Params>
  void dispatch(Kernel& k, const LaunchGrid& grid, std::initializer_list<const Buffer*> buffers, const Params& params) {
    static_assert(std::is_trivially_copyable_v<Params>);
    dispatch_raw(k, grid, buffers, &params, sizeof(Params), &typeid(Params));
  }
  // `params_type` nullptr: not checked (kernels built from explicit sources take any bytes).
  void dispatch_raw(Kernel& k, const LaunchGrid& grid, std::initializer_list<const Buffer*> buffers,
                    const void* params, size_t params_bytes, const std::type_info* params_type = nullptr);
  void dispatch_raw(Kernel& k, uint32_t groups, uint32_t local_size, std::initializer_list<const Buffer*> buffers,
                    const void* params, size_t params_bytes, const std::type_info* params_type = nullptr) {
    dispatch_raw(k, LaunchGrid{{groups, 1}, {local_size, 1}}, buffers, params, params_bytes, params_type);
  }
  void barrier();
  // A point in the stream. submit() starts the work recorded so far and returns at once with its mark; the
  // host goes on while the device runs it. wait(mark) returns once that work has finished: what it wrote can
  // then be read (host_view, download). Marks grow (1, 2, ...); waiting for one waits for every earlier one,
  // and waiting again returns at once. Buffers destroyed meanwhile return to the pool at finish().
  using StreamMark = uint64_t;
  StreamMark submit();
  void wait(StreamMark mark);
  void finish();
  // finish(), then gives the storage of every device allocation that holds no buffers back to the system (later
  // allocations make new ones). Where device memory is host memory (CPU devices) a host stage that follows a
  // device stage then reuses pages the device already touched instead of fresh ones, whose first touch is slow.
  void trim();

  // Timings of the dispatches finished since the last call (empty unless opened with profile = true).
  std::vector<KernelTiming> take_timings();
  // Nanoseconds the host has spent blocked on this device since it was opened: in wait() and finish(), in
  // upload() and download() (which wait for earlier work, their copy included), and where a backend drains its
  // stream by itself. Always counted (profiling or not); a stage reads it before and after itself.
  uint64_t host_wait_ns() const;

  // Groups for a grid-stride dispatch covering `items` with `local_size`, capped at the device limit.
  uint32_t groups_for(uint64_t items, uint32_t local_size) const;

  // For runtime tests: build a kernel from explicit sources (bypassing the embedded registry).
  // `args_in_buffer`: the SPIR-V reads its arguments through a parameter buffer (compiled with MV_ARGS_BUFFER).
  Kernel& kernel_from_source(const std::string& name, const char* cl_source, const uint32_t* spirv,
                             size_t spirv_words, bool args_in_buffer = false);

 private:
  Kernel& add_kernel(const rt::KernelDesc& desc);
  Device() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mv

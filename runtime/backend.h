// The one small interface every compute backend implements (OpenCL, Vulkan).
// Nothing above runtime/ sees this header: host code talks to mv::Device (include/megavox/device.h).
#pragma once
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "megavox/device.h"  // DeviceInfo, KernelTiming

namespace mv::rt {

// A kernel as embedded at build time: OpenCL C source (all includes inlined) and SPIR-V.
struct KernelDesc {
  std::string name;            // entry point name, unique across all kernels (e.g. "radix_scatter_k64")
  std::string cl_program;      // name of the OpenCL program that holds the entry (built once per device)
  const char* cl_source = nullptr;
  const uint32_t* spirv = nullptr;  // one SPIR-V module per kernel, entry "main"
  size_t spirv_words = 0;
  bool args_in_buffer = false;  // Vulkan: the module reads its arguments from a parameter buffer (MV_ARGS_BUFFER)
  int declared_args = -1;       // buffers + 1 as kernels/kernels.cmake declares; OpenCL checks it (-1: unchecked)
};

// One large device allocation; the memory pool carves pages out of it.
class BackendArena {
 public:
  virtual ~BackendArena() = default;
  // Where the device computes in host memory (CPU devices), the arena's storage as the host sees it; else null.
  // The pool touches fresh ranges of it from all cores before handing them out (host/base/huge_pages.h prefault).
  void* host = nullptr;
};

// A byte range [offset, offset + bytes) of an arena, usable as a kernel argument.
class BackendBuffer {
 public:
  virtual ~BackendBuffer() = default;
};

class BackendKernel {
 public:
  virtual ~BackendKernel() = default;
};

// All work is ordered in one stream per backend. dispatch/fill/copy are recorded (OpenCL: enqueued on an
// in-order queue; Vulkan: recorded into a command buffer), start running no later than the next submit() and
// finish no later than the wait() for its mark or finish(). barrier() makes every earlier write visible to every
// later command; without one, consecutive commands may overlap.
// upload/download are synchronous: they wait for all earlier work, then copy. upload_async is recorded in the
// stream like copy: it returns at once and the copy runs in order with the other commands (OpenCL: a
// non-blocking write, `src` read while it runs; Vulkan: `src` copied into staging memory now, then a recorded
// copy); the caller keeps `src` unchanged until the copy has finished.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual const DeviceInfo& info() const = 0;

  virtual std::unique_ptr<BackendArena> create_arena(uint64_t bytes) = 0;  // throws mv::Error on failure
  virtual std::unique_ptr<BackendBuffer> create_buffer(BackendArena& arena, uint64_t offset, uint64_t bytes) = 0;
  // The buffer's bytes as the host sees them where the device computes in host memory (its arena's `host`);
  // nullptr elsewhere.
  virtual const void* host_pointer(BackendBuffer&) const { return nullptr; }

  virtual void upload(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) = 0;
  virtual void download(BackendBuffer& src, uint64_t offset, void* dst, uint64_t bytes) = 0;
  virtual void upload_async(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) = 0;
  // Fill `bytes` (multiple of 4) at `offset` (multiple of 4) with a 32-bit pattern; recorded in the stream.
  virtual void fill(BackendBuffer& dst, uint64_t offset, uint64_t bytes, uint32_t pattern) = 0;
  // Copy `bytes` (multiple of 4) between buffers; recorded in the stream.
  virtual void copy(BackendBuffer& src, uint64_t src_offset, BackendBuffer& dst, uint64_t dst_offset,
                    uint64_t bytes) = 0;


  // Built once per backend instance and cached by desc.name. A build failure throws mv::Error naming
  // the kernel (OpenCL: with the compiler log; Vulkan: the rejected module or pipeline).
  virtual BackendKernel& kernel(const KernelDesc& desc) = 0;

  // Arguments: the buffers in order (null for an empty Buffer, which the kernel must not touch), then one
  // trivially-copyable parameter struct (may be empty).
  // OpenCL: kernel(global T* b0, ..., global T* bk, Params p). Vulkan: push constants
  // { uint64_t address of b0 .. bk; Params p; } (at most kMaxPushBytes in all), or for kernels built with
  // MV_ARGS_BUFFER that block in a parameter buffer and its address pushed (at most kMaxArgBytes).
  virtual void dispatch(BackendKernel& kernel, const LaunchGrid& grid, std::span<BackendBuffer* const> buffers,
                        const void* params, size_t params_bytes) = 0;
  virtual void barrier() = 0;
  // Stream marks (1, 2, ...). submit() starts every command recorded so far and returns at once with a mark of
  // that point; wait(mark) blocks until the commands before the mark have finished, their writes visible to the
  // host. Waiting for a mark waits for every earlier one; a mark already waited for (or finished) returns at once.
  virtual uint64_t submit() = 0;
  virtual void wait(uint64_t mark) = 0;
  virtual void finish() = 0;  // submit() and wait for everything

  // Per-dispatch device timings (kernel name, nanoseconds, work-items), collected while profiling is on.
  virtual void set_profiling(bool on) = 0;
  virtual std::vector<KernelTiming> take_timings() = 0;

  // Nanoseconds the host has spent in Blocking scopes (Device::host_wait_ns).
  uint64_t blocked_ns() const { return blocked_ns_.load(std::memory_order_relaxed); }

  // Told before (done false) and after (done true) each compile the kernel cache could not spare, naming what
  // compiles; set by Device (DeviceOptions::on_compile).
  std::function<void(const std::string& what, bool done)> on_compile;

 protected:
  // Wraps each call that blocks the host on the device (a fence or event wait, a blocking transfer); nested
  // scopes (a download that finishes the stream first) count once.
  class Blocking {
   public:
    explicit Blocking(Backend& b) : b_(b), start_(std::chrono::steady_clock::now()) { ++b.blocking_depth_; }
    ~Blocking() {
      if (--b_.blocking_depth_ == 0)
        b_.blocked_ns_.fetch_add(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     std::chrono::steady_clock::now() - start_).count(),
                                 std::memory_order_relaxed);
    }
    Blocking(const Blocking&) = delete;
    Blocking& operator=(const Blocking&) = delete;

   private:
    Backend& b_;
    std::chrono::steady_clock::time_point start_;
  };

  // Runs `compile` between the two calls of on_compile; one that throws is announced as ended too.
  template <class F>
  auto announced_compile(const std::string& what, F&& compile) {
    if (on_compile) on_compile(what, false);
    struct End {
      const Backend& backend;
      const std::string& what;
      ~End() {
        if (backend.on_compile) backend.on_compile(what, true);
      }
    } end{*this, what};
    return compile();
  }

 private:
  std::atomic<uint64_t> blocked_ns_{0};
  int blocking_depth_ = 0;
};

inline constexpr size_t kMaxPushBytes = 128;  // Vulkan's guaranteed minimum push-constant size
// Most argument bytes (8 per buffer, then the parameters) one dispatch takes: past the push constants they go
// through a parameter buffer on Vulkan (MV_ARGS_BUFFER); within OpenCL's guaranteed 1 KiB of kernel arguments.
inline constexpr size_t kMaxArgBytes = 1024;

// Discovery. Each list is in the API's enumeration order; index i opens the i-th entry.
std::vector<DeviceInfo> enumerate_opencl();
std::vector<DeviceInfo> enumerate_vulkan();
// `kernel_cache`: the folder of compiled programs, or of Vulkan's records of the pipelines the driver compiled
// (empty: KernelCache::default_dir()).
std::unique_ptr<Backend> open_opencl(int index, const std::string& kernel_cache);
std::unique_ptr<Backend> open_vulkan(int index, const std::string& kernel_cache);

}  // namespace mv::rt

// mv::Device: a backend, its page pool and its kernels behind one backend-neutral class.
#include "megavox/device.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <utility>
#include <vector>

#include "backend.h"
#include "kernel_table.h"
#include "megavox/error.h"
#include "memory_pool.h"

#if defined(MEGAVOX_TSAN)
#include <tbb/global_control.h>
// The TSan build (scripts/test.sh --sanitize=thread) checks megavox's own threads: the C API's jobs, the
// service's workers and HTTP threads. libtbb is not instrumented, so TSan cannot see the synchronisation between
// its workers and reports every parallel loop; there TBB runs its loops on the calling thread alone.
static tbb::global_control tsan_tbb_on_calling_thread(tbb::global_control::max_allowed_parallelism, 1);
#endif

namespace mv {

namespace {
constexpr uint64_t kPageBytes = 64 << 10;
}  // namespace

struct Device::Impl {
  DeviceInfo info;  // the backend's, with the launch shape asked for
  std::unique_ptr<rt::Backend> backend;
  std::unique_ptr<rt::MemoryPool> pool;
  std::map<std::string, std::unique_ptr<Kernel>, std::less<>> kernels;
};

// ---- Buffer ----

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    pool_ = std::exchange(other.pool_, nullptr);
    arena_ = other.arena_;
    first_page_ = other.first_page_;
    pages_ = other.pages_;
    bytes_ = std::exchange(other.bytes_, 0);
    impl_ = std::move(other.impl_);
  }
  return *this;
}

Buffer::~Buffer() { release(); }

void Buffer::ImplDeleter::operator()(rt::BackendBuffer* b) const { delete b; }

void Buffer::release() {
  impl_.reset();
  if (pool_) pool_->release({arena_, first_page_, pages_});
  pool_ = nullptr;
  bytes_ = 0;
}

// ---- Device ----

std::unique_ptr<Device> Device::open(const DeviceOptions& options) {
  DeviceInfo chosen = select_device(options.selector);
  std::unique_ptr<Device> device(new Device());
  device->impl_ = std::make_unique<Impl>();
  auto& impl = *device->impl_;
  impl.backend = chosen.backend == "opencl" ? rt::open_opencl(chosen.index, options.kernel_cache)
                                            : rt::open_vulkan(chosen.index, options.kernel_cache);
  if (options.on_compile)
    impl.backend->on_compile = [listener = options.on_compile, device = impl.backend->info().name,
                                count = uint32_t{0}](const std::string& what, bool done) mutable {
      if (!done) ++count;
      listener({device, what, count, done});
    };
  impl.info = impl.backend->info();
  KernelShape shape = options.kernel_shape;
  if (shape == KernelShape::automatic)
    if (const char* env = std::getenv("MEGAVOX_KERNEL_SHAPE"); env && *env) shape = parse_kernel_shape(env);
  apply_kernel_shape(impl.info, shape);
  const DeviceInfo& info = impl.info;
  uint64_t budget = options.memory_budget;
  if (budget == 0) {
    budget = info.global_memory_bytes / 4 * 3 / std::max(1u, options.budget_share);  // room for the driver and others
  } else if (budget > info.global_memory_bytes) {
    throw CodedError(ErrorCode::invalid_argument,
                     "the device memory budget " + format_bytes(budget) + " is more than " + info.name + " has (" +
                         format_bytes(info.global_memory_bytes) + ")",
                     setting_device_memory);
  }
  impl.pool = std::make_unique<rt::MemoryPool>(*impl.backend, budget, kPageBytes, info.max_allocation_bytes);
  impl.backend->set_profiling(options.profile);
  return device;
}

Device::~Device() {
  if (impl_ && impl_->backend) {
    try {
      impl_->backend->finish();
    } catch (...) {
    }
  }
}

const DeviceInfo& Device::info() const { return impl_->info; }
uint64_t Device::memory_budget() const { return impl_->pool->budget(); }
uint64_t Device::memory_used() const { return impl_->pool->used(); }
uint64_t Device::memory_peak() const { return impl_->pool->peak(); }
void Device::reset_memory_peak() { impl_->pool->reset_peak(); }
uint64_t Device::page_bytes() const { return impl_->pool->page_bytes(); }

Buffer Device::alloc(uint64_t bytes, std::string_view what) {
  Buffer buf;
  if (bytes == 0) return buf;
  auto range = impl_->pool->allocate(bytes, what);
  buf.pool_ = impl_->pool.get();
  buf.arena_ = range.arena;
  buf.first_page_ = range.first_page;
  buf.pages_ = range.pages;
  buf.bytes_ = bytes;
  try {
    buf.impl_.reset(impl_->backend->create_buffer(impl_->pool->arena(range.arena), range.first_page * page_bytes(),
                                                  range.pages * page_bytes())
                        .release());
  } catch (...) {
    buf.release();
    throw;
  }
  return buf;
}

namespace {
void check_range(const Buffer& b, uint64_t offset, uint64_t bytes, const char* op) {
  if (offset > b.bytes() || bytes > b.bytes() - offset)
    throw Error(std::string(op) + ": range [" + std::to_string(offset) + ", +" + std::to_string(bytes) +
                ") is outside a buffer of " + std::to_string(b.bytes()) + " bytes");
}
}  // namespace

void Device::upload(Buffer& dst, const void* src, uint64_t bytes, uint64_t offset) {
  check_range(dst, offset, bytes, "upload");
  if (bytes) impl_->backend->upload(*dst.impl_, offset, src, bytes);
}

void Device::upload_async(Buffer& dst, const void* src, uint64_t bytes, uint64_t offset) {
  check_range(dst, offset, bytes, "upload");
  if (bytes) impl_->backend->upload_async(*dst.impl_, offset, src, bytes);
}

void Device::download(const Buffer& src, void* dst, uint64_t bytes, uint64_t offset) const {
  check_range(src, offset, bytes, "download");
  if (bytes) impl_->backend->download(*src.impl_, offset, dst, bytes);
}

const void* Device::host_view(const Buffer& buffer) const {
  return buffer.impl_ ? impl_->backend->host_pointer(*buffer.impl_) : nullptr;
}

void Device::fill(Buffer& dst, uint32_t pattern, uint64_t bytes, uint64_t offset) {
  check_range(dst, offset, bytes, "fill");
  if (bytes % 4 || offset % 4) throw Error("fill: offset and size must be multiples of 4");
  if (bytes) impl_->backend->fill(*dst.impl_, offset, bytes, pattern);
}

void Device::copy(const Buffer& src, Buffer& dst, uint64_t bytes, uint64_t src_offset, uint64_t dst_offset) {
  check_range(src, src_offset, bytes, "copy");
  check_range(dst, dst_offset, bytes, "copy");
  if (bytes % 4 || src_offset % 4 || dst_offset % 4) throw Error("copy: offsets and size must be multiples of 4");
  if (bytes) impl_->backend->copy(*src.impl_, src_offset, *dst.impl_, dst_offset, bytes);
}

Kernel& Device::kernel(KernelId id) {
  const rt::EmbeddedKernel* e = rt::find_embedded_kernel(id);
  if (!e) throw Error("no embedded kernel with id " + std::to_string(static_cast<uint32_t>(id)));
  return kernel(*e);
}

Kernel& Device::kernel(const rt::EmbeddedKernel& entry) {
  const rt::EmbeddedKernel* e = &entry;
  if (auto it = impl_->kernels.find(e->name); it != impl_->kernels.end()) return *it->second;
  if (std::string lacks = rt::missing_features(info(), e->signature.needs); !lacks.empty())
    throw Error("device '" + info().name + "' (" + info().selector() + ") is unsuitable for kernel '" + e->name +
                "' (program " + e->cl_program + "): it lacks " + lacks);
  rt::KernelDesc desc;
  desc.name = e->name;
  desc.cl_program = e->cl_program;  // kernels of one program share its build
  desc.cl_source = e->cl_source;
  desc.spirv = e->spirv;
  desc.spirv_words = e->spirv_words;
  desc.args_in_buffer = e->signature.args_in_buffer;
  desc.declared_args = static_cast<int>(e->signature.buffers) + 1;
  Kernel& k = add_kernel(desc);
  k.checked_ = true;
  k.buffers_ = e->signature.buffers;
  k.params_type_ = e->signature.params;
  k.params_bytes_ = e->signature.params_bytes;
  k.params_name_ = e->signature.params_name;
  return k;
}

Kernel& Device::kernel_from_source(const std::string& name, const char* cl_source, const uint32_t* spirv,
                                   size_t spirv_words, bool args_in_buffer) {
  rt::KernelDesc desc;
  desc.name = name;
  desc.cl_program = name;
  desc.cl_source = cl_source;
  desc.spirv = spirv;
  desc.spirv_words = spirv_words;
  desc.args_in_buffer = args_in_buffer;
  return add_kernel(desc);
}

Kernel& Device::add_kernel(const rt::KernelDesc& desc) {
  if (auto it = impl_->kernels.find(desc.name); it != impl_->kernels.end()) return *it->second;
  auto k = std::make_unique<Kernel>();
  k->name_ = desc.name;
  k->impl_ = &impl_->backend->kernel(desc);
  return *impl_->kernels.emplace(desc.name, std::move(k)).first->second;
}

void Device::dispatch_raw(Kernel& k, const LaunchGrid& grid, std::initializer_list<const Buffer*> buffers,
                          const void* params, size_t params_bytes, const std::type_info* params_type) {
  if (k.checked_) {
    if (buffers.size() != k.buffers_)
      throw Error("kernel '" + k.name() + "': dispatched with " + std::to_string(buffers.size()) +
                  " buffers, but kernels/kernels.cmake declares " + std::to_string(k.buffers_));
    if (params_type && *params_type != *k.params_type_)
      throw Error("kernel '" + k.name() + "': dispatched with parameters of another type (" +
                  std::to_string(params_bytes) + " bytes) than the " + k.params_name_ + " (" +
                  std::to_string(k.params_bytes_) + " bytes) kernels/kernels.cmake declares");
    if (params_bytes != k.params_bytes_)
      throw Error("kernel '" + k.name() + "': dispatched with " + std::to_string(params_bytes) +
                  " parameter bytes, but its " + k.params_name_ + " has " + std::to_string(k.params_bytes_));
  }
  const uint64_t items = uint64_t{grid.local[0]} * grid.local[1];
  if (grid.local[0] == 0 || grid.local[1] == 0 || items > info().max_work_group_size)
    throw Error("kernel '" + k.name() + "': work-group size " + std::to_string(grid.local[0]) + "x" +
                std::to_string(grid.local[1]) + " is not in [1, " + std::to_string(info().max_work_group_size) +
                "] items");
  if (grid.groups[1] > std::max<uint32_t>(info().max_groups_y, 1))
    throw Error("kernel '" + k.name() + "': " + std::to_string(grid.groups[1]) + " groups along y exceed the device "
                "limit of " + std::to_string(info().max_groups_y));
  std::vector<rt::BackendBuffer*> bufs;
  bufs.reserve(buffers.size());
  for (const Buffer* b : buffers) bufs.push_back(b ? b->impl_.get() : nullptr);
  impl_->backend->dispatch(*k.impl_, grid, bufs, params, params_bytes);
}

void Device::barrier() { impl_->backend->barrier(); }
Device::StreamMark Device::submit() { return impl_->backend->submit(); }
void Device::wait(StreamMark mark) { impl_->backend->wait(mark); }
void Device::finish() {
  impl_->backend->finish();
  impl_->pool->reclaim();
}
void Device::trim() {
  finish();
  impl_->pool->trim();
}
std::vector<KernelTiming> Device::take_timings() { return impl_->backend->take_timings(); }
uint64_t Device::host_wait_ns() const { return impl_->backend->blocked_ns(); }

uint32_t Device::groups_for(uint64_t items, uint32_t local_size) const {
  uint64_t groups = (items + local_size - 1) / local_size;
  return static_cast<uint32_t>(std::clamp<uint64_t>(groups, 1, info().max_groups));
}

KernelShape parse_kernel_shape(std::string_view text) {
  if (text == "auto") return KernelShape::automatic;
  if (text == "gpu") return KernelShape::gpu;
  if (text == "cpu") return KernelShape::cpu;
  throw CodedError(ErrorCode::invalid_argument,
                   "the kernel shape '" + std::string(text) + "' is none of auto, gpu, cpu (--kernel-shape, "
                   "MEGAVOX_KERNEL_SHAPE)");
}

const char* kernel_shape_name(KernelShape shape) {
  return shape == KernelShape::gpu ? "gpu" : shape == KernelShape::cpu ? "cpu" : "auto";
}

void apply_kernel_shape(DeviceInfo& info, KernelShape shape) {
  const bool gpu = shape == KernelShape::automatic ? info.type == "gpu" : shape == KernelShape::gpu;
  info.massively_parallel = gpu;
  // GPU-shaped: work-groups of 64 (two warps, one wavefront). CPU-shaped: PoCL runs a work-group's items as a
  // loop, so one item a group; a Vulkan CPU driver runs one subgroup in lock step, so a group of its width.
  const uint32_t preferred = gpu ? 64 : info.backend == "vulkan" ? std::max<uint32_t>(info.simd_width, 1) : 1;
  info.preferred_work_group_size = std::min(preferred, std::max<uint32_t>(info.max_work_group_size, 1));
}

namespace rt {

std::string missing_features(const DeviceInfo& info, uint32_t needs) {
  std::string lacks;
  auto need = [&](uint32_t bit, bool has, const char* what) {
    if ((needs & bit) && !has) lacks += (lacks.empty() ? "" : ", ") + std::string(what);
  };
  need(kNeedsATOMICS64, info.atomics64, "64-bit atomics on global memory");
  need(kNeedsSHARED_ATOMICS64, info.shared_atomics64, "64-bit atomics on work-group shared memory");
  return lacks;
}

}  // namespace rt
}  // namespace mv

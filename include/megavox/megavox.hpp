// megavox — a thin C++ RAII layer over the C API (megavox.h), header only: handles that retain on copy and
// release on destruction, and a megavox::Error (with the MvError code) thrown where a C call failed.
// It uses only the C API, so it carries the C API's stability promise.
#pragma once
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "megavox/megavox.h"

namespace megavox {

class Error : public std::runtime_error {
 public:
  Error(MvError code, const std::string& message) : std::runtime_error(message), code_(code) {}
  MvError code() const { return code_; }

 private:
  MvError code_;
};

namespace detail {

// A reference-counted handle: Retain / Release are the C API's pair for H.
template <class H, void (*Retain)(H), void (*Release)(H)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(H h) : h_(h) {}  // adopts one reference
  Handle(const Handle& o) : h_(o.h_) { if (h_) Retain(h_); }
  Handle(Handle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Handle& operator=(Handle o) noexcept {
    std::swap(h_, o.h_);
    return *this;
  }
  ~Handle() { if (h_) Release(h_); }
  H get() const { return h_; }
  explicit operator bool() const { return h_ != nullptr; }

 private:
  H h_ = nullptr;
};

// The error `device` recorded (NULL: this thread's), as an exception.
[[noreturn]] inline void raise(MvDevice device, MvError code = MV_ERROR_NONE) {
  const std::string message = mvGetDeviceLastErrorMessage(device);
  const MvError recorded = mvGetDeviceError(device);
  throw Error(code != MV_ERROR_NONE ? code : recorded, message);
}

inline void check(MvDevice device, MvError code) {
  if (code != MV_ERROR_NONE) raise(device, code);
}

}  // namespace detail

class Scene;
class Job;

class Device : public detail::Handle<MvDevice, mvRetainDevice, mvReleaseDevice> {
 public:
  Device() = default;
  // See mvNewDevice for the config keys ("device=vk:0,memory=512M").
  explicit Device(const std::string& config) : Handle(mvNewDevice(config.c_str())) {
    if (!get()) detail::raise(nullptr);
  }
  MvDeviceInfo info() const {
    MvDeviceInfo i;
    detail::check(get(), mvGetDeviceInfo(get(), &i));
    return i;
  }
  void set_error_function(MvErrorFunction f, void* user) { mvSetDeviceErrorFunction(get(), f, user); }

  inline Scene open(const std::string& path) const;
  inline Scene build(const std::string& path, const MvBuildArguments* args = nullptr) const;
  inline Scene build(const std::vector<float>& vertices, const std::vector<uint32_t>& indices,
                     const MvBuildArguments* args = nullptr) const;
  inline Job build_async(const std::string& path, const MvBuildArguments* args = nullptr) const;

  // Point-cloud builds and masks: files in, a file (or a 3D Tiles folder) out.
  void build_points(const std::string& input, const std::string& output, const MvPointBuildArguments* args = nullptr) const {
    detail::check(get(), mvBuildPointsFile(get(), input.c_str(), output.c_str(), args));
  }
  inline Job build_points_async(const std::string& input, const std::string& output,
                                const MvPointBuildArguments* args = nullptr) const;
  void mask(const std::string& input, const std::string& output, const MvMaskArguments& args) const {
    detail::check(get(), mvMaskImageFile(get(), input.c_str(), output.c_str(), &args));
  }
  inline Job mask_async(const std::string& input, const std::string& output, const MvMaskArguments& args) const;
};

class Scene : public detail::Handle<MvScene, mvRetainScene, mvReleaseScene> {
 public:
  Scene() = default;
  Scene(MvScene s, MvDevice device) : Handle(s), device_(device) {
    if (!s) detail::raise(device);
  }
  MvSceneInfo info() const {
    MvSceneInfo i;
    detail::check(device_, mvGetSceneInfo(get(), &i));
    return i;
  }
  void save(const std::string& path) const { detail::check(device_, mvSaveScene(get(), path.c_str())); }
  // Whether its queries stream through a page cache, and what they loaded and held (mvGetSceneStats).
  MvSceneStats stats() const {
    MvSceneStats s{};
    s.byteSize = sizeof s;
    detail::check(device_, mvGetSceneStats(get(), &s));
    return s;
  }
  std::vector<MvTraceHit> trace(const std::vector<MvTraceRay>& rays, const MvTraceArguments* args = nullptr) const {
    std::vector<MvTraceHit> hits(rays.size());
    detail::check(device_, mvTraceRays(get(), rays.data(), hits.data(), rays.size(), args));
    return hits;
  }
  // As trace, with each hit's colour into rgba (4 bytes per ray; all 0 for a miss or a scene without colours).
  std::vector<MvTraceHit> trace(const std::vector<MvTraceRay>& rays, std::vector<uint8_t>& rgba,
                                const MvTraceArguments* args = nullptr) const {
    std::vector<MvTraceHit> hits(rays.size());
    rgba.assign(rays.size() * 4, 0);
    detail::check(device_, mvTraceRaysRgba(get(), rays.data(), hits.data(), rgba.data(), rays.size(), args));
    return hits;
  }
  // Colours stored (voxels and inner nodes): 0 without colours.
  uint64_t colour_entries() const {
    uint64_t n = 0;
    detail::check(device_, mvGetSceneColourEntries(get(), &n));
    return n;
  }
  // RGBA, 4 bytes per pixel, rows top first.
  std::vector<uint8_t> render(const MvRenderArguments& args, const MvCamera* camera = nullptr) const {
    std::vector<uint8_t> rgba(size_t{args.width} * args.height * 4);
    detail::check(device_, mvRenderScene(get(), camera, &args, rgba.data(), 0));
    return rgba;
  }

 private:
  MvDevice device_ = nullptr;  // for its error record; the scene keeps the device alive
};

class Job : public detail::Handle<MvJob, mvRetainJob, mvReleaseJob> {
 public:
  Job() = default;
  Job(MvJob j, MvDevice device) : Handle(j), device_(device) {
    if (!j) detail::raise(device);
  }
  MvJobStatus status(double* fraction = nullptr) const { return mvGetJobStatus(get(), fraction); }
  std::string message() const { return mvGetJobMessage(get()); }
  void cancel() const { mvCancelJob(get()); }
  // Waits; throws megavox::Error when the job failed or was cancelled.
  void finish() const {
    const MvError e = mvWaitJob(get());
    if (e != MV_ERROR_NONE) throw Error(e, message());
  }
  // finish(), then the scene a build job made.
  Scene wait() const {
    finish();
    return Scene(mvGetJobScene(get()), device_);
  }

 private:
  MvDevice device_ = nullptr;
};

Scene Device::open(const std::string& path) const { return Scene(mvOpenScene(get(), path.c_str()), get()); }
Scene Device::build(const std::string& path, const MvBuildArguments* args) const {
  return Scene(mvBuildSceneFromFile(get(), path.c_str(), args), get());
}
Scene Device::build(const std::vector<float>& vertices, const std::vector<uint32_t>& indices,
                    const MvBuildArguments* args) const {
  return Scene(mvBuildSceneFromMemory(get(), vertices.data(), vertices.size() / 3, indices.data(), indices.size() / 3, args),
               get());
}
Job Device::build_async(const std::string& path, const MvBuildArguments* args) const {
  return Job(mvBuildSceneFromFileAsync(get(), path.c_str(), args), get());
}
Job Device::build_points_async(const std::string& input, const std::string& output,
                               const MvPointBuildArguments* args) const {
  return Job(mvBuildPointsFileAsync(get(), input.c_str(), output.c_str(), args), get());
}
Job Device::mask_async(const std::string& input, const std::string& output, const MvMaskArguments& args) const {
  return Job(mvMaskImageFileAsync(get(), input.c_str(), output.c_str(), &args), get());
}

// RGBA pixels (rows top first, width * 4 bytes each) to a PNG, or a JPEG for .jpg / .jpeg.
inline void write_image(const std::string& path, const std::vector<uint8_t>& rgba, uint32_t width, uint32_t height) {
  detail::check(nullptr, mvWriteImage(path.c_str(), rgba.data(), width, height, 0));
}

}  // namespace megavox

// What the C API's opaque handles hold, and the guard every entry point runs its body in (so no exception
// crosses the API: each becomes an MvError recorded on the device).
#pragma once
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <string>

#include "megavox/device.h"
#include "megavox/error.h"
#include "megavox/megavox.h"
#include "megavox/mvx.h"
#include "megavox/trace.h"

namespace mv::capi {

// Thrown inside the API to fail with a chosen code (a bad argument, a cancelled build, ...). ErrorCode's values
// are MvError's.
struct ApiError : CodedError {
  ApiError(MvError c, const std::string& m) : CodedError(static_cast<ErrorCode>(c), m) {}
};

// A reference count shared by the handle kinds.
struct RefCounted {
  std::atomic<int> refs{1};
};

}  // namespace mv::capi

struct MvDeviceTy : mv::capi::RefCounted {
  std::unique_ptr<mv::Device> device;
  uint64_t host_memory = 0;   // builds' host RAM budget; 0 = the default
  uint64_t cache_memory = 0;  // scenes' page cache when set (cache_memory=); 0: only where a scene does not fit
  // Serialises every call on the device (mv::Device has no locking); recursive so that a progress or error
  // function may call back into the API on the same thread.
  std::recursive_mutex lock;
  std::mutex error_lock;  // the error record below
  MvError error = MV_ERROR_NONE;
  std::string message;
  MvErrorFunction error_function = nullptr;
  void* error_user = nullptr;
};

struct MvSceneTy : mv::capi::RefCounted {
  MvDevice device = nullptr;  // retained
  // The scene's .mvx. mvOpenScene opens it at once; a build's scene opens the file it wrote on first use, so a
  // caller that wants only the file (a job, the service) never reads it back.
  std::string path;
  std::string scratch;  // a build's own file when its caller named none: removed with the scene

  // What the scene is, from the file opened once (capi/scene_query.cpp): a paged .mvx is mapped and kept paged
  // (its header and page index checked now, each page checked when read); any other is read whole and checked.
  // Throws mv::Error; a later call tries again.
  struct Facts {
    mv::Encoding encoding = mv::Encoding::svdag;
    mv::GridTransform grid;
    mv::Bounds bounds;
    uint32_t levels = 0;
    uint64_t voxels = 0, bytes = 0, colour_entries = 0;
  };
  Facts facts();
  const mv::MvxFile& file();  // the whole file, read on demand (a save; a resident trace of an unpaged file)

  // Under the device lock. The tracer: resident when the nodes fit what is left of the device budget and the
  // device sets no cache_memory, else streaming through a page cache.
  mv::Tracer& tracer_locked();
  // Exact ray queries: every ray resolved (batches retried smaller where the cache cannot hold their pages).
  std::vector<mv::RayHit> trace_locked(const std::vector<mv::Ray>& rays, const mv::TraceOptions& options,
                                       std::vector<uint32_t>* colours);
  // Rays per batch that fit the device beside the scene (at most `wanted`).
  size_t ray_batch_locked(size_t wanted);
  MvSceneStats stats_locked();
  void note_peak_locked();  // after a call: the device's peak so far counts toward the scene's
  ~MvSceneTy();

 private:
  void open();
  std::mutex open_lock_;
  bool opened_ = false;
  std::shared_ptr<const mv::PagedDag> paged_;  // a paged file
  std::unique_ptr<mv::MvxFile> file_;          // read whole
  std::unique_ptr<mv::Tracer> tracer_;
  uint64_t passes_ = 0, pages_streamed_ = 0, peak_ = 0;
};

// A .mvx point hierarchy read whole (capi/c_points_read.cpp).
struct MvPointsTy : mv::capi::RefCounted {
  MvDevice device = nullptr;  // retained: the error record of calls on it
  mv::PointHierarchy hierarchy;
  ~MvPointsTy();
};

namespace mv::capi {

// mvRetain* / mvRelease* of every handle kind: the last release deletes (destructors never throw out).
template <class H>
void retain(H* h) {
  if (h) h->refs.fetch_add(1);
}
template <class H>
void release(H* h) noexcept {
  if (h && h->refs.fetch_sub(1) == 1) {
    try {
      delete h;
    } catch (...) {
    }
  }
}

// One reference held for a scope: what a call works on stays alive when a callback (a progress or error
// function) or another thread drops the caller's last reference meanwhile.
template <class H>
class Hold {
 public:
  explicit Hold(H* h) : h_(h) { retain(h_); }
  ~Hold() { release(h_); }
  Hold(const Hold&) = delete;
  Hold& operator=(const Hold&) = delete;

 private:
  H* h_;
};

// Records an error on `device` (or this thread's record when null) and calls its error function.
void record_error(MvDevice device, MvError code, const std::string& message);

// Runs `body`, turning any exception into an error recorded on `device`; returns MV_ERROR_NONE or the code
// (and the message through `message_out` when given). The device is held for the call.
template <class F>
MvError guard(MvDevice device, F&& body, std::string* message_out = nullptr) noexcept {
  const Hold<MvDeviceTy> keep(device);
  MvError code = MV_ERROR_UNKNOWN;
  std::string message;
  try {
    body();
    return MV_ERROR_NONE;
  } catch (const std::exception& e) {
    code = static_cast<MvError>(classify(e));
    message = error_message(e);
  } catch (...) {
    message = "an unknown exception";
  }
  try {
    if (message_out) *message_out = message;
    record_error(device, code, message);
  } catch (...) {
  }
  return code;
}

// Throws ApiError(MV_ERROR_INVALID_ARGUMENT) with `what` when `ok` is false.
inline void require(bool ok, const char* what) {
  if (!ok) throw ApiError(MV_ERROR_INVALID_ARGUMENT, what);
}

// Copies `text` into a fixed C array, cut to fit and NUL-terminated.
template <size_t N>
void copy_text(char (&out)[N], const std::string& text) {
  const size_t n = text.size() < N - 1 ? text.size() : N - 1;
  text.copy(out, n);
  out[n] = '\0';
}

}  // namespace mv::capi

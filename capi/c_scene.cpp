// The C API: scenes (build, open, save, describe), ray queries and pictures.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "scene_build.h"
#include "io/output_path.h"
#include "megavox/render.h"

using namespace mv::capi;

namespace {

constexpr size_t kRayBatch = size_t{1} << 20;  // rays per device round trip

MvDevice scene_device(MvScene scene) { return scene ? scene->device : nullptr; }

}  // namespace

extern "C" {

void mvInitBuildArguments(MvBuildArguments* args) {
  if (!args) return;
  *args = MvBuildArguments{};
  args->byteSize = sizeof(MvBuildArguments);
  args->format = "svdag";
}

MvScene mvBuildSceneFromFile(MvDevice device, const char* path, const MvBuildArguments* args) {
  MvScene scene = nullptr;
  guard(device, [&] {
    require(device, "mvBuildSceneFromFile: no device");
    scene = build_scene(device, file_input(path), build_options(device, args), user_progress(args));
  });
  return scene;
}

MvScene mvBuildSceneFromMemory(MvDevice device, const float* vertices, size_t vertexCount, const uint32_t* indices,
                               size_t triangleCount, const MvBuildArguments* args) {
  MvScene scene = nullptr;
  guard(device, [&] {
    require(device, "mvBuildSceneFromMemory: no device");
    scene = build_scene(device, memory_input(vertices, vertexCount, indices, triangleCount, false),
                        build_options(device, args), user_progress(args));
  });
  return scene;
}

MvScene mvBuildSceneFromMemoryRgb(MvDevice device, const float* vertices, size_t vertexCount, const uint32_t* indices,
                                  size_t triangleCount, const uint8_t* rgb, const MvBuildArguments* args) {
  MvScene scene = nullptr;
  guard(device, [&] {
    require(device, "mvBuildSceneFromMemoryRgb: no device");
    scene = build_scene(device, memory_input(vertices, vertexCount, indices, triangleCount, false, rgb),
                        build_options(device, args), user_progress(args));
  });
  return scene;
}

MvScene mvOpenScene(MvDevice device, const char* path) {
  MvScene made = nullptr;
  guard(device, [&] {
    require(device, "mvOpenScene: no device");
    require(path && *path, "mvOpenScene: no path");
    auto scene = std::make_unique<MvSceneTy>();
    scene->path = path;
    scene->facts();  // opened and checked now
    mvRetainDevice(device);
    scene->device = device;
    made = scene.release();
  });
  return made;
}

void mvRetainScene(MvScene scene) { retain(scene); }

void mvReleaseScene(MvScene scene) { release(scene); }

MvError mvSaveScene(MvScene scene, const char* path) {
  return guard(scene_device(scene), [&] {
    require(scene, "mvSaveScene: no scene");
    const Hold<MvSceneTy> keep(scene);
    require(path && *path, "mvSaveScene: no path");
    // The scene is in memory, so its own file may be rewritten; a FIFO, a device or a folder may not.
    mv::write_mvx(mv::io::resolve_output({path, mv::io::OutputKind::kFile, "mvx"}), scene->file());
  });
}

MvError mvGetSceneInfo(MvScene scene, MvSceneInfo* info) {
  return guard(scene_device(scene), [&] {
    require(scene, "mvGetSceneInfo: no scene");
    const Hold<MvSceneTy> keep(scene);
    require(info, "mvGetSceneInfo: info is NULL");
    const MvSceneTy::Facts f = scene->facts();
    *info = MvSceneInfo{};
    copy_text(info->encoding, mv::encoding_name(f.encoding));
    info->resolution = f.grid.resolution;
    info->levels = f.levels;
    info->voxels = f.voxels;
    info->bytes = f.bytes;
    info->voxelSize = f.grid.voxel_size;
    for (int a = 0; a < 3; ++a) {
      info->origin[a] = f.grid.origin[a];
      info->lower[a] = f.bounds.lo[a];
      info->upper[a] = f.bounds.hi[a];
    }
  });
}

void mvInitTraceArguments(MvTraceArguments* args) {
  if (!args) return;
  *args = MvTraceArguments{};
  args->byteSize = sizeof(MvTraceArguments);
  args->maxSteps = mv::TraceOptions{}.max_steps;
}

MvError mvTraceRays(MvScene scene, const MvTraceRay* rays, MvTraceHit* hits, size_t count, const MvTraceArguments* args) {
  return mvTraceRaysRgba(scene, rays, hits, nullptr, count, args);
}

MvError mvGetSceneStats(MvScene scene, MvSceneStats* stats) {
  return guard(scene_device(scene), [&] {
    require(scene && stats, "mvGetSceneStats: scene or stats is NULL");
    require(stats->byteSize == sizeof(MvSceneStats), "mvGetSceneStats: stats->byteSize must be sizeof(MvSceneStats)");
    const Hold<MvSceneTy> keep(scene);
    std::lock_guard<std::recursive_mutex> g(scene->device->lock);
    *stats = scene->stats_locked();
  });
}

MvError mvGetSceneColourEntries(MvScene scene, uint64_t* entries) {
  return guard(scene_device(scene), [&] {
    require(scene && entries, "mvGetSceneColourEntries: scene or entries is NULL");
    const Hold<MvSceneTy> keep(scene);
    std::lock_guard<std::recursive_mutex> g(scene->device->lock);
    // the colours its queries return: none where it streams a file without a size plane (version 4 and before)
    *entries = scene->tracer_locked().has_colours() ? scene->facts().colour_entries : 0;
  });
}

MvError mvTraceRaysRgba(MvScene scene, const MvTraceRay* rays, MvTraceHit* hits, uint8_t* rgba, size_t count,
                        const MvTraceArguments* args) {
  return guard(scene_device(scene), [&] {
    require(scene, "mvTraceRays: no scene");
    const Hold<MvSceneTy> keep(scene);
    require((rays && hits) || count == 0, "mvTraceRays: rays or hits is NULL");
    mv::TraceOptions options;
    if (args) {
      require(args->byteSize == sizeof(MvTraceArguments), "mvTraceRays: MvTraceArguments.byteSize is wrong (call mvInitTraceArguments)");
      options.max_steps = args->maxSteps;
    }
    std::lock_guard<std::recursive_mutex> g(scene->device->lock);
    scene->device->device->reset_memory_peak();
    const size_t per_batch = count ? scene->ray_batch_locked(kRayBatch) : 1;
    std::vector<mv::Ray> batch;
    for (size_t first = 0; first < count; first += per_batch) {
      const size_t n = std::min(per_batch, count - first);
      batch.resize(n);
      for (size_t i = 0; i < n; ++i) {
        const MvTraceRay& r = rays[first + i];
        for (int a = 0; a < 3; ++a) {
          batch[i].origin[a] = r.org[a];
          batch[i].direction[a] = r.dir[a];
        }
        batch[i].tmax = r.tmax;
      }
      std::vector<uint32_t> colours;
      const std::vector<mv::RayHit> got = scene->trace_locked(batch, options, rgba ? &colours : nullptr);
      scene->note_peak_locked();
      if (rgba)
        for (size_t i = 0; i < n; ++i)
          for (int k = 0; k < 4; ++k) rgba[4 * (first + i) + k] = colours.empty() ? 0 : colours[i] >> (8 * k) & 255;
      for (size_t i = 0; i < n; ++i) {
        const mv::RayHit& h = got[i];
        MvTraceHit& out = hits[first + i];
        out.t = h.hit ? h.t : h.gave_up ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
        out.level = h.hit ? h.level : 0;
        for (int a = 0; a < 3; ++a) {
          out.cell[a] = h.hit ? h.cell[a] : 0;
          out.normal[a] = h.hit ? h.normal[a] : 0;
        }
      }
    }
  });
}

void mvInitRenderArguments(MvRenderArguments* args) {
  if (!args) return;
  const mv::RenderOptions d;
  *args = MvRenderArguments{};
  args->byteSize = sizeof(MvRenderArguments);
  args->width = d.width;
  args->height = d.height;
  args->shading = "shaded";
  args->view = "iso";
  args->lodPixels = d.lod_pixels;
  args->aoSamples = d.ao_samples;
}

MvError mvGetSceneViewCamera(MvScene scene, const char* view, double fov, MvCamera* camera) {
  return guard(scene_device(scene), [&] {
    require(scene, "mvGetSceneViewCamera: no scene");
    const Hold<MvSceneTy> keep(scene);
    require(camera, "mvGetSceneViewCamera: camera is NULL");
    require(fov >= 0 && fov < 180, "mvGetSceneViewCamera: fov must be 0 (the default) or between 0 and 180 degrees");
    mv::Camera c;
    try {
      c = mv::view_camera(scene->facts().bounds, view ? view : "iso", fov > 0 ? fov : MV_DEFAULT_FOV);
    } catch (const mv::Error& e) {
      throw ApiError(MV_ERROR_INVALID_ARGUMENT, e.what());
    }
    for (int a = 0; a < 3; ++a) {
      camera->eye[a] = c.eye[a];
      camera->target[a] = c.target[a];
      camera->up[a] = c.up[a];
    }
    camera->fov = c.fov;
  });
}

MvError mvRenderScene(MvScene scene, const MvCamera* camera, const MvRenderArguments* args, uint8_t* rgba,
                      size_t rowStride) {
  return guard(scene_device(scene), [&] {
    require(scene, "mvRenderScene: no scene");
    const Hold<MvSceneTy> keep(scene);
    require(args, "mvRenderScene: args is NULL (call mvInitRenderArguments)");
    require(args->byteSize == sizeof(MvRenderArguments), "mvRenderScene: MvRenderArguments.byteSize is wrong (call mvInitRenderArguments)");
    require(rgba, "mvRenderScene: rgba is NULL");
    require(args->width >= 1 && args->height >= 1 && args->width <= 16384 && args->height <= 16384,
            "mvRenderScene: width and height must be 1 to 16384");
    const size_t stride = rowStride ? rowStride : size_t{args->width} * 4;
    require(stride >= size_t{args->width} * 4, "mvRenderScene: rowStride is below width * 4");
    mv::RenderOptions o;
    o.width = args->width;
    o.height = args->height;
    try {
      o.shading = mv::parse_shading(args->shading ? args->shading : "shaded");
    } catch (const mv::Error& e) {
      throw ApiError(MV_ERROR_INVALID_ARGUMENT, e.what());
    }
    require(args->lodPixels >= 0 && std::isfinite(args->lodPixels), "mvRenderScene: lodPixels must be >= 0");
    require(args->aoSamples <= 256, "mvRenderScene: aoSamples must be at most 256");
    o.lod_pixels = args->lodPixels;
    o.ao_samples = args->aoSamples;
    mv::Camera cam;
    if (camera) {
      for (int a = 0; a < 3; ++a) {
        cam.eye[a] = camera->eye[a];
        cam.target[a] = camera->target[a];
        cam.up[a] = camera->up[a];
      }
      cam.fov = camera->fov;
      require(cam.fov > 0 && cam.fov < 180, "mvRenderScene: fov must be between 0 and 180 degrees");
    } else {
      try {
        cam = mv::view_camera(scene->facts().bounds, args->view ? args->view : "iso");
      } catch (const mv::Error& e) {
        throw ApiError(MV_ERROR_INVALID_ARGUMENT, e.what());
      }
    }
    std::lock_guard<std::recursive_mutex> g(scene->device->lock);
    scene->device->device->reset_memory_peak();
    const mv::RenderResult r = mv::render(scene->tracer_locked(), cam, o);
    scene->note_peak_locked();
    for (uint32_t y = 0; y < o.height; ++y) {
      uint8_t* row = rgba + y * stride;
      const uint8_t* src = r.image.rgb.data() + size_t{y} * o.width * 3;
      for (uint32_t x = 0; x < o.width; ++x) {
        std::memcpy(row + 4 * x, src + 3 * x, 3);
        row[4 * x + 3] = 255;
      }
    }
  });
}

}  // extern "C"

#include "scene_build.h"

#include "job.h"

#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#include "option_words.h"

namespace mv::capi {

namespace {

// A fresh name for a build whose caller wants no file: reserved by mkstemp in $TMPDIR; the scene removes it.
std::string scratch_mvx() {
  const char* dir = std::getenv("TMPDIR");
  std::string pattern = std::string(dir && *dir ? dir : "/tmp") + "/megavox-scene-XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = mkstemp(name.data());
  if (fd < 0) throw IoError("cannot make a scratch file in " + std::string(dir && *dir ? dir : "/tmp"));
  close(fd);
  return name.data();
}

std::string text_or(const char* s, const char* fallback) { return s ? s : fallback; }


}  // namespace

BuildInput file_input(const char* path) {
  require(path && *path, "build: no input path");
  BuildInput in;
  in.path = path;
  return in;
}

BuildInput memory_input(const float* vertices, size_t vertex_count, const uint32_t* indices, size_t triangles, bool copy,
                        const uint8_t* rgb) {
  require(vertices || vertex_count == 0, "build: vertices is NULL");
  require(indices || triangles == 0, "build: indices is NULL");
  require(vertex_count <= SIZE_MAX / 3 && triangles <= SIZE_MAX / 3, "build: array sizes overflow");
  BuildInput in;
  std::span<const float> p(vertices, vertex_count * 3);
  std::span<const uint32_t> i(indices, triangles * 3);
  if (copy) {
    in.positions.assign(p.begin(), p.end());
    in.indices.assign(i.begin(), i.end());
    p = in.positions;
    i = in.indices;
  }
  if (rgb) {
    in.colours.resize(vertex_count);
    for (size_t v = 0; v < vertex_count; ++v)
      in.colours[v] = uint32_t{rgb[3 * v]} | uint32_t{rgb[3 * v + 1]} << 8 | uint32_t{rgb[3 * v + 2]} << 16;
  }
  in.mesh = {p, i, in.colours};
  return in;
}

BuildOptions build_options(MvDevice device, const MvBuildArguments* args) {
  BuildOptions o;
  o.memory = device->host_memory;
  if (!args) return o;
  require(args->byteSize == sizeof(MvBuildArguments), "build: MvBuildArguments.byteSize is wrong (call mvInitBuildArguments)");
  o.encoding = parse_encoding(text_or(args->format, "svdag"));
  o.resolution = args->resolution;
  // 0 is "unset", as in every other field, so a zeroed struct builds as the CLI and the service do.
  o.cube = args->cube == 0 ? kDefaultCube : args->cube == MV_CUBE_IN_CORE ? 0 : args->cube;
  o.voxelize = parse_voxelize_rule(text_or(args->voxelize, "conservative"));
  o.grid = text_or(args->grid, "");
  if (args->gridOrigin) o.placement = parse_grid_origin(args->gridOrigin);
  o.output = text_or(args->output, "");
  if (o.resolution && (o.resolution < 2 || (o.resolution & (o.resolution - 1)) || o.resolution > (1u << 21)))
    throw ApiError(MV_ERROR_INVALID_ARGUMENT, "build: resolution " + std::to_string(o.resolution) +
                                                  " is not a power of two from 2 to 2^21");
  return o;
}

Progress user_progress(const MvBuildArguments* args) {
  return args ? user_progress(args->progress, args->progressUserPtr, "build") : Progress{};
}

MvScene build_scene(MvDevice device, const BuildInput& input, BuildOptions o, const Progress& progress) {
  auto scene = std::make_unique<MvSceneTy>();  // its destructor removes the scratch file on any failure
  if (o.output.empty()) o.output = scene->scratch = scratch_mvx();
  scene->path = o.output;
  if (input.path.empty()) {
    o.input = "mesh in memory";
    o.mesh = &input.mesh;
  } else {
    o.input = input.path;
  }
  {
    std::lock_guard<std::recursive_mutex> g(device->lock);
    build_mvx(*device->device, o, progress);
  }
  mvRetainDevice(device);
  scene->device = device;
  return scene.release();  // the file it wrote is read on first use (MvSceneTy::file)
}

}  // namespace mv::capi

// Builds behind mvBuildScene* and the build jobs: the C arguments checked and copied into BuildOptions, then
// build_mvx on the device; the scene is the written .mvx, read on its first use.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "handles.h"
#include "megavox/build.h"

namespace mv::capi {

// A build's input: a file, or mesh arrays (owned here for jobs; views of the caller's for a call).
struct BuildInput {
  std::string path;  // empty: the arrays
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> colours;  // per vertex 0xBBGGRR, always owned (packed from the caller's R, G, B)
  MeshArrays mesh;  // what the build reads: views of the vectors above or of the caller's arrays
};

BuildInput file_input(const char* path);
// `copy`: own the arrays (a job outlives the call). `rgb`: NULL, or 3 bytes per vertex.
BuildInput memory_input(const float* vertices, size_t vertex_count, const uint32_t* indices, size_t triangles, bool copy,
                        const uint8_t* rgb = nullptr);

// The options of `args` (NULL: defaults), strings copied. Throws ApiError for an args struct of the wrong size.
BuildOptions build_options(MvDevice device, const MvBuildArguments* args);

// Runs the build under the device lock and returns the scene (one reference) of the file it wrote, not read
// back yet. `progress` may throw to stop.
MvScene build_scene(MvDevice device, const BuildInput& input, BuildOptions options, const Progress& progress);

// The caller's progress function as a Progress that throws ApiError(MV_ERROR_CANCELLED) when it returns false.
Progress user_progress(const MvBuildArguments* args);

}  // namespace mv::capi

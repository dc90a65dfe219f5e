#include "job_words.h"

#include "option_words.h"

namespace mv::serve {

namespace {

const OptionWords kWords[] = {
    // the library's CLI flags
    {"--cube", "\"cube\""},
    {"--resolution", "\"resolution\""},
    {"--format", "\"format\""},
    {"--voxelize", "\"voxelize\""},
    {"--grid-origin", "\"grid_origin\""},
    {"--width", "\"width\""},
    {"--height", "\"height\""},
    {"--view", "\"view\""},
    {"--shading", "\"shading\""},
    {"--eye", "\"eye\""},
    {"--target", "\"target\""},
    {"--up", "\"up\""},
    {"--fov", "\"fov\""},
    {"--depth", "\"depth\""},
    {"--max-node-points", "\"max_node_points\""},
    {"--rect", "\"rect\""},
    {"--seeds", "\"seeds\""},
    {"--model", "\"model\""},
    {"--iterations", "\"iterations\""},
    {"--erode", "\"erode\""},
    {"--memory", "the server's host memory per job"},
    {"--device-memory", "the server's device memory per job"},
    // the C API's, which words the failures of the build jobs run through it (capi/scene_build.cpp)
    {"MvBuildArguments.cube", "\"cube\""},
    {"MvBuildArguments.resolution", "\"resolution\""},
    {"MvBuildArguments.format", "\"format\""},
    {"MvBuildArguments.voxelize", "\"voxelize\""},
    {"MvBuildArguments.gridOrigin", "\"grid_origin\""},
    {"host_memory (mvNewDevice)", "the server's host memory per job"},
    {"memory (mvNewDevice)", "the server's device memory per job"},
};

}  // namespace

std::string in_job_terms(const std::string& message) { return reword_options(message, kWords); }

}  // namespace mv::serve

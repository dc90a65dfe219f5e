// A triangle mesh held in the caller's memory (the C API's build from vertex and index arrays), read in place.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "io/mesh_source.h"

namespace mv::io {

// `positions`: 3 floats per vertex; `indices`: 3 per triangle; `colours`: empty, or one 0xBBGGRR per vertex.
// The arrays must outlive the source. Throws mv::Error (naming `label`) for a position that is not finite, an
// index past the vertices, or a ragged array; the checks run before any triangle is handed out.
std::unique_ptr<MeshSource> memory_mesh(std::span<const float> positions, std::span<const uint32_t> indices,
                                        const std::string& label, std::span<const uint32_t> colours = {});

}  // namespace mv::io

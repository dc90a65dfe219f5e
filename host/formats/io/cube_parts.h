// A partial DAG as bytes (what an MPI rank sends for a cube) and the files `build --resume` keeps of finished
// cubes: OUTPUT.cubes/cube-N.part, each with its build's fingerprint and a checksum, so only the same build
// reuses it and a damaged one is made again. Internal to megavox; not a public format.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "megavox/dag_types.h"

namespace mv::io {

std::vector<uint8_t> pack_dag(const Dag& dag);
// Throws mv::Error on bytes that are not a packed DAG. `used`: the bytes the DAG took (more may follow);
// null: the DAG must fill `bytes`.
Dag unpack_dag(const std::vector<uint8_t>& bytes, size_t* used = nullptr);

// The kept file of `cube` in `dir`.
std::string cube_part_path(const std::string& dir, uint64_t cube);
// Writes `bytes` (a packed part and its payload) under a temporary name, then renames it.
void write_cube_part(const std::string& dir, uint64_t cube, uint64_t fingerprint, const std::vector<uint8_t>& bytes);
// The bytes kept for `cube`, or nullopt when there is no file, or it is of another build, or damaged.
std::optional<std::vector<uint8_t>> read_cube_part(const std::string& dir, uint64_t cube, uint64_t fingerprint);

}  // namespace mv::io

// read_cube_part and unpack_dag (host/formats/io/cube_parts.h): the cubes `build --resume` keeps on disk, and the
// partial DAGs MPI ranks send. Each input is read as a packed DAG, then as a kept cube file both as it is and
// with its header rewritten to match (fingerprint, cube, size, checksum), so mutations get past the checks.
#include <unistd.h>
#include <xxhash.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "fuzz_support.h"
#include "io/cube_parts.h"
#include "megavox/error.h"

namespace {

void unpack(const std::vector<uint8_t>& bytes) {
  try {
    size_t used = 0;
    const mv::Dag d = mv::io::unpack_dag(bytes, &used);
    MV_FUZZ_CHECK(used <= bytes.size());
    MV_FUZZ_CHECK(d.level.size() == d.levels + 1u);
  } catch (const mv::Error&) {
  }
}

// A folder of this process's own, removed when it ends.
struct KeptDir {
  std::string path = std::filesystem::temp_directory_path().string() + "/mvfuzz-cube-" + std::to_string(getpid());
  KeptDir() { std::filesystem::create_directories(path); }
  ~KeptDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

const std::string& kept_dir() {
  static const KeptDir dir;
  return dir.path;
}

void read_file(const std::vector<uint8_t>& file) {
  {
    std::ofstream out(mv::io::cube_part_path(kept_dir(), 7), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  }
  if (auto bytes = mv::io::read_cube_part(kept_dir(), 7, 42)) unpack(*bytes);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  unpack(bytes);
  read_file(bytes);
  // The same bytes as the body of a kept cube whose header checks out.
  struct {
    char magic[8] = {'M', 'V', 'C', 'U', 'B', 'E', '1', '\0'};
    uint64_t fingerprint = 42, cube = 7, bytes = 0, checksum = 0;
  } h;
  h.bytes = size;
  h.checksum = XXH64(data, size, 0);
  std::vector<uint8_t> file(sizeof h);
  std::memcpy(file.data(), &h, sizeof h);
  file.insert(file.end(), data, data + size);
  read_file(file);
  return 0;
}

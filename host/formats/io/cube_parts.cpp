#include "io/cube_parts.h"

#include <xxhash.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "megavox/error.h"

namespace mv::io {

namespace {

constexpr char kMagic[8] = {'M', 'V', 'C', 'U', 'B', 'E', '1', '\0'};

template <class T>
void put(std::vector<uint8_t>& out, const T& v) {
  const auto* p = reinterpret_cast<const uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

template <class T>
void put_vector(std::vector<uint8_t>& out, const std::vector<T>& v) {
  put(out, uint64_t{v.size()});
  const auto* p = reinterpret_cast<const uint8_t*>(v.data());
  out.insert(out.end(), p, p + v.size() * sizeof(T));
}

struct Reader {
  const std::vector<uint8_t>& bytes;
  size_t at = 0;
  template <class T>
  T get() {
    if (bytes.size() - at < sizeof(T)) throw Error("a packed partial DAG is cut short");
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<uint64_t>();
    if (n > (bytes.size() - at) / sizeof(T)) throw Error("a packed partial DAG is cut short");
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
    at += n * sizeof(T);
    return v;
  }
};

// Header of a kept cube: magic, fingerprint, cube, byte count, then XXH64 of the bytes.
struct PartHeader {
  char magic[8];
  uint64_t fingerprint, cube, bytes, checksum;
};

}  // namespace

std::vector<uint8_t> pack_dag(const Dag& dag) {
  std::vector<uint8_t> out;
  put(out, dag.levels);
  put(out, uint8_t{dag.symmetric});
  put(out, uint8_t{dag.reduced});
  put(out, dag.voxels);
  put_vector(out, dag.svo_nodes);
  put(out, uint64_t{dag.level.size()});
  for (const DagLevel& l : dag.level) {
    put_vector(out, l.mask);
    put_vector(out, l.first);
    put_vector(out, l.children);
    put_vector(out, l.tags);
  }
  return out;
}

Dag unpack_dag(const std::vector<uint8_t>& bytes, size_t* used) {
  Reader in{bytes};
  Dag dag;
  dag.levels = in.get<uint32_t>();
  dag.symmetric = in.get<uint8_t>() != 0;
  dag.reduced = in.get<uint8_t>() != 0;
  dag.voxels = in.get<uint64_t>();
  dag.svo_nodes = in.get_vector<uint64_t>();
  const auto levels = in.get<uint64_t>();
  if (levels != uint64_t{dag.levels} + 1 || dag.levels > 21) throw Error("a packed partial DAG has a wrong level count");
  dag.level.resize(levels);
  for (DagLevel& l : dag.level) {
    l.mask = in.get_vector<uint32_t>();
    l.first = in.get_vector<uint32_t>();
    l.children = in.get_vector<uint32_t>();
    l.tags = in.get_vector<uint32_t>();
  }
  if (used) *used = in.at;
  else if (in.at != bytes.size()) throw Error("a packed partial DAG has bytes past its end");
  return dag;
}

std::string cube_part_path(const std::string& dir, uint64_t cube) {
  return dir + "/cube-" + std::to_string(cube) + ".part";
}

void write_cube_part(const std::string& dir, uint64_t cube, uint64_t fingerprint, const std::vector<uint8_t>& bytes) {
  PartHeader h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.fingerprint = fingerprint;
  h.cube = cube;
  h.bytes = bytes.size();
  h.checksum = XXH64(bytes.data(), bytes.size(), 0);
  const std::string path = cube_part_path(dir, cube), temp = path + ".writing";
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw IoError("cannot write the kept cube " + temp);
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) throw IoError("cannot rename the kept cube " + temp);
}

std::optional<std::vector<uint8_t>> read_cube_part(const std::string& dir, uint64_t cube, uint64_t fingerprint) {
  const std::string path = cube_part_path(dir, cube);
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in || size < sizeof(PartHeader)) return std::nullopt;
  PartHeader h{};
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 ||
      h.fingerprint != fingerprint || h.cube != cube || h.bytes != size - sizeof h)
    return std::nullopt;
  std::vector<uint8_t> bytes(h.bytes);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())) ||
      in.peek() != std::char_traits<char>::eof() || XXH64(bytes.data(), bytes.size(), 0) != h.checksum)
    return std::nullopt;
  return bytes;
}

}  // namespace mv::io

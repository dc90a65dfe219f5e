#include "tiles_archive.h"

#include <openssl/evp.h>
#include <zip.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "serve_error.h"

namespace mv::serve {

namespace {

namespace fs = std::filesystem;

// `write` fills a temporary file beside `path`, which is synced and then renamed over it: a reader (the
// result route) sees no archive or the whole of it, never a part.
void write_by_rename(const std::string& path, const std::function<void(const std::string& tmp)>& write) {
  const std::string tmp = path + ".tmp";
  const auto fail = [&](const std::string& why, MvError code) {
    std::remove(tmp.c_str());
    throw ServeError("cannot write '" + path + "': " + why, code);
  };
  try {
    write(tmp);
  } catch (const ServeError& e) {
    fail(e.what(), e.code);
  } catch (const std::exception& e) {
    fail(message_of(e), code_of(e) == MV_ERROR_UNKNOWN ? MV_ERROR_IO : code_of(e));
  }
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  const int err = errno;
  if (fd >= 0) ::close(fd);
  if (!synced) fail(std::string("cannot sync it to disk: ") + std::strerror(err), MV_ERROR_IO);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(std::string("cannot rename it: ") + std::strerror(errno), MV_ERROR_IO);
}

// minizip's default file functions, with the stream they open kept: the index needs each entry's local header
// offset, which is where the file stands when the entry is opened (minizip 1.1 has no call that says it).
struct ZipFile {
  zlib_filefunc64_def io{};
  open64_file_func open = nullptr;
  voidpf stream = nullptr;
  zipFile zip = nullptr;

  static voidpf open_keeping(voidpf opaque, const void* name, int mode) {
    auto* self = static_cast<ZipFile*>(opaque);
    self->stream = self->open(opaque, name, mode);  // the default functions ignore `opaque`
    return self->stream;
  }
  explicit ZipFile(const std::string& path) {
    fill_fopen64_filefunc(&io);
    open = io.zopen64_file;
    io.zopen64_file = open_keeping;
    io.opaque = this;
    zip = zipOpen2_64(path.c_str(), APPEND_STATUS_CREATE, nullptr, &io);
    if (!zip) throw ServeError("3D Tiles archive " + path + ": cannot create it", MV_ERROR_IO);
  }
  ~ZipFile() {
    if (zip) zipClose(zip, nullptr);
  }
  uint64_t offset() const { return io.ztell64_file(io.opaque, stream); }
};

struct IndexEntry {
  std::array<uint8_t, 16> md5;
  uint64_t offset;
};

uint64_t le64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | p[i];
  return v;
}

std::array<uint8_t, 16> md5(const std::string& text) {
  std::array<uint8_t, 16> h{};
  unsigned int n = 0;
  if (!EVP_Digest(text.data(), text.size(), h.data(), &n, EVP_md5(), nullptr) || n != 16)
    throw ServeError("3D Tiles archive: MD5 is not available", MV_ERROR_UNKNOWN);
  return h;
}

void add_entry(ZipFile& z, const std::string& name, const char* data, size_t size, const std::string& path) {
  zip_fileinfo info{};
  info.tmz_date = {0, 0, 0, 1, 0, 1980};  // a fixed date: the same tiles make the same archive
  // stored (method 0), and no zip64 extra: the format caps entries at 4 GB with their sizes in the local header
  if (zipOpenNewFileInZip64(z.zip, name.c_str(), &info, nullptr, 0, nullptr, 0, nullptr, 0, 0, 0) != ZIP_OK ||
      (size && zipWriteInFileInZip(z.zip, data, static_cast<unsigned>(size)) != ZIP_OK) || zipCloseFileInZip(z.zip) != ZIP_OK)
    throw ServeError("3D Tiles archive " + path + ": cannot write " + name, MV_ERROR_IO);
}

}  // namespace

void write_3tz(const std::string& dir, const std::string& path) {
  std::vector<std::string> names;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file()) names.push_back(fs::relative(it->path(), dir).generic_string());
  if (ec) throw ServeError("3D Tiles archive: cannot list " + dir + ": " + ec.message(), MV_ERROR_IO);
  // tileset.json first (a reader scanning the archive meets the root first), then the tiles in name order
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    return (a == "tileset.json") != (b == "tileset.json") ? a == "tileset.json" : a < b;
  });
  if (names.empty() || names.front() != "tileset.json") throw ServeError("3D Tiles archive: " + dir + " holds no tileset.json", MV_ERROR_INPUT);
  write_by_rename(path, [&](const std::string& tmp) {
    ZipFile z(tmp);
    std::vector<IndexEntry> index;
    std::vector<char> bytes;
    for (const std::string& name : names) {
      std::ifstream in(fs::path(dir) / name, std::ios::binary | std::ios::ate);
      if (!in) throw ServeError("3D Tiles archive: cannot read " + name, MV_ERROR_IO);
      const auto size = static_cast<uint64_t>(in.tellg());
      if (size >= (uint64_t{1} << 32)) throw ServeError("3D Tiles archive: " + name + " is over the format's 4 GB per file", MV_ERROR_INPUT);
      bytes.resize(size);
      in.seekg(0);
      if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) throw ServeError("3D Tiles archive: cannot read " + name, MV_ERROR_IO);
      index.push_back({md5(name), z.offset()});
      add_entry(z, name, bytes.data(), bytes.size(), path);
    }
    std::sort(index.begin(), index.end(), [](const IndexEntry& a, const IndexEntry& b) {
      const uint64_t ah = le64(a.md5.data()), bh = le64(b.md5.data());
      return ah != bh ? ah < bh : le64(a.md5.data() + 8) < le64(b.md5.data() + 8);
    });
    std::string table;
    for (const IndexEntry& e : index) {
      table.append(reinterpret_cast<const char*>(e.md5.data()), 16);
      for (int i = 0; i < 8; ++i) table.push_back(static_cast<char>(e.offset >> (8 * i) & 0xff));
    }
    add_entry(z, "@3dtilesIndex1@", table.data(), table.size(), path);  // the last entry, as readers look for it
    const int closed = zipClose(z.zip, nullptr);
    z.zip = nullptr;
    if (closed != ZIP_OK) throw ServeError("3D Tiles archive " + path + ": cannot finish it", MV_ERROR_IO);
  });
}

}  // namespace mv::serve

#include "output_path.h"

#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "megavox/error.h"

namespace mv::io {

namespace fs = std::filesystem;

namespace {

struct Extension {
  const char* ext;
  const char* format;
};
// Lower case, with the dot. Formats megavox writes, and formats it only reads (an output named like an input
// format is almost always a slip of the keyboard).
constexpr Extension kExtensions[] = {
    {".mvx", "mvx"},          {".png", "png"},     {".jpg", "jpeg"},   {".jpeg", "jpeg"},
    {".vdb", "vdb"},          {".nvdb", "nvdb"},   {".svdag", "symvox-svdag"},
    {".ussvdag", "symvox-ussvdag"},                {".ssvdag", "symvox-ssvdag"},
    {".mvm", "mvm"},          {".3tz", "3tz"},     {".ply", "ply"},    {".las", "las"},
    {".laz", "laz"},          {".obj", "obj"},     {".stl", "stl"},    {".gltf", "gltf"},
    {".glb", "glb"},          {".fbx", "fbx"},     {".json", "json"},  {".ppm", "ppm"},
    {".pgm", "pgm"},          {".tif", "tiff"},    {".tiff", "tiff"},  {".exr", "exr"}};

const char* kind_of(mode_t m) {
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
  if (S_ISSOCK(m)) return "a socket";
  if (S_ISDIR(m)) return "a folder";
  return "not a regular file";
}

[[noreturn]] void refuse(const std::string& path, const std::string& why, Setting settings = setting_none) {
  throw IoError("cannot write '" + path + "': " + why, settings);
}

// Follows symbolic links in the last part of `path` (up to 40, as the kernel does): the file they name.
std::string follow_links(const std::string& path) {
  std::string p = path;
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::error_code ec;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) refuse(path, "cannot read the link '" + p + "': " + ec.message());
    p = target.is_absolute() ? target.string() : (fs::path(p).parent_path() / target).string();
  }
  refuse(path, "too many levels of symbolic links");
}

bool under(const fs::path& child, const fs::path& root) {
  auto c = child.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++c)
    if (c == child.end() || *c != *r) return false;
  return true;
}

// Device and process files are no place for output, even where one looks like a regular file
// (/proc/self/fd/1 when standard output is redirected to a file).
void refuse_system_paths(const std::string& shown, const std::string& path) {
  std::error_code ec;
  const fs::path given = fs::absolute(path, ec).lexically_normal();
  const fs::path resolved = fs::weakly_canonical(given, ec);
  auto system = [](const fs::path& p) {
    return (under(p, "/dev") && !under(p, "/dev/shm")) || under(p, "/proc") || under(p, "/sys");
  };
  if (system(given) || (!ec && system(resolved)))
    refuse(shown, "it is under /dev, /proc or /sys, a place for devices and streams, not files; megavox writes "
                  "files by name (give a file in a folder of yours)");
}

// The folder the output goes in: it must exist, be a folder and be writable.
std::string check_folder(const std::string& shown, const std::string& path) {
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  struct stat st {};
  if (::stat(parent.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOTDIR)
      refuse(shown, "a part of '" + parent.string() + "' is a file, not a folder");
    if (err == ENOENT) refuse(shown, "the folder '" + parent.string() + "' does not exist (create it first)");
    refuse(shown, "cannot reach the folder '" + parent.string() + "': " + std::strerror(err));
  }
  if (!S_ISDIR(st.st_mode)) refuse(shown, "'" + parent.string() + "' is a file, not a folder");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    refuse(shown, "the folder '" + parent.string() + "' is not writable: " + std::strerror(errno));
  return parent.string();
}

void check_free_space(const std::string& shown, const std::string& folder, uint64_t bytes) {
  struct statvfs vfs {};
  if (bytes == 0 || ::statvfs(folder.c_str(), &vfs) != 0) return;
  const uint64_t free_bytes = uint64_t(vfs.f_bavail) * vfs.f_frsize;
  if (free_bytes < bytes) {
    char text[160];
    std::snprintf(text, sizeof text, "it needs about %.1f MiB and '%s' has %.1f MiB free", bytes / 1048576.0,
                  folder.c_str(), free_bytes / 1048576.0);
    refuse(shown, text);
  }
}

void check_extension(const std::string& shown, const std::string& path, const std::string& format) {
  if (format.empty()) return;
  const std::string says = format_of_extension(path);
  if (says.empty() || says == format) return;
  std::string want;
  for (const Extension& e : kExtensions)
    if (format == e.format) {
      want = e.ext;
      break;
    }
  refuse(shown, "its name says " + says + " but " + format + " is what would be written" +
                    (want.empty() ? std::string() : "; name it with " + want));
}

void check_not_input(const std::string& shown, const std::string& target, const OutputRequest& r) {
  std::error_code ec;
  struct stat out {};
  const bool exists = ::stat(target.c_str(), &out) == 0;
  const fs::path folder = fs::weakly_canonical(fs::absolute(target, ec), ec);
  for (const std::string& in : r.inputs) {
    if (in.empty()) continue;
    struct stat st {};
    if (exists && ::stat(in.c_str(), &st) == 0 && st.st_dev == out.st_dev && st.st_ino == out.st_ino)
      refuse(shown, r.kind == OutputKind::kFolder ? "it is the input '" + in + "'"
                                                   : "it is the input '" + in + "' (the same file); writing it "
                                                     "would destroy what is being read: choose another name");
    if (r.kind == OutputKind::kFolder && exists) {
      const fs::path input = fs::weakly_canonical(fs::absolute(in, ec), ec);
      if (under(input, folder))
        refuse(shown, "the folder holds the input '" + in + "', and writing it replaces the whole folder");
    }
  }
}

}  // namespace

std::string format_of_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const Extension& e : kExtensions)
    if (ext == e.ext) return e.format;
  return "";
}

unsigned current_umask() {
  // Linux 4.7+ shows it; elsewhere umask() must be set to be read, which no other thread may see half-done.
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("Umask:", 0) == 0) return unsigned(std::stoul(line.substr(6), nullptr, 8));
  static std::mutex m;
  std::lock_guard<std::mutex> lock(m);
  const mode_t old = ::umask(022);
  ::umask(old);
  return old;
}

void check_output_folder(const std::string& dir) {
  refuse_system_paths(dir, dir);
  fs::path p = fs::path(dir).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "out/" -> "out"
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) refuse(dir, std::string("it is ") + kind_of(st.st_mode) + ", not a folder");
    if (::access(p.c_str(), W_OK | X_OK) != 0) refuse(dir, std::string("the folder is not writable: ") + std::strerror(errno));
    return;
  }
  if (errno == ENOTDIR) refuse(dir, "a part of it is a file, not a folder");
  // Missing: its nearest existing parent must be a folder it can be made in.
  fs::path parent = p.parent_path();
  while (!parent.empty() && ::stat(parent.c_str(), &st) != 0) parent = parent.parent_path();
  if (parent.empty()) parent = ".";
  check_folder(dir, (parent / "x").string());
}

std::string resolve_output(const OutputRequest& r) {
  const std::string& shown = r.path;
  if (r.path.empty()) throw Error("no output named (-o PATH)");
  refuse_system_paths(shown, r.path);
  std::string target = r.path;
  if (r.kind == OutputKind::kFolder) {
    while (target.size() > 1 && target.back() == '/') target.pop_back();  // "out/" -> "out"
  } else {
    if (r.path.back() == '/') refuse(shown, "it names a folder; a file name is needed here");
    target = follow_links(r.path);
    if (target != r.path) refuse_system_paths(shown, target);
  }
  const std::string folder = check_folder(shown, target);

  struct stat st {};
  const bool exists = ::stat(target.c_str(), &st) == 0;
  if (exists) {
    if (r.kind == OutputKind::kFile && !S_ISREG(st.st_mode))
      refuse(shown, std::string("it is ") + kind_of(st.st_mode) + "; megavox replaces only regular files");
    if (r.kind == OutputKind::kFolder && !S_ISDIR(st.st_mode))
      refuse(shown, "it exists and is not a folder; remove it or choose another name");
  }
  check_not_input(shown, target, r);
  if (exists && r.no_clobber) {
    std::error_code ec;
    if (r.kind == OutputKind::kFile || !fs::is_empty(target, ec))
      refuse(shown, "it exists and replacing outputs was refused", setting_no_clobber);
  }
  check_extension(shown, target, r.format);
  check_free_space(shown, folder, r.estimated_bytes);
  return target;
}

}  // namespace mv::io

#include "voxcom_peer.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "scratch_dir.h"
#include "io/vdb_source.h"
#include "megavox/error.h"
#include "stopwatch.h"

namespace mv::bench {

namespace {

// The last `lines` lines of `text`, for an error message.
std::string tail(const std::string& text, int lines) {
  size_t end = text.size();
  if (text.empty()) return "(no output)";
  if (end > 0 && text[end - 1] == '\n') --end;
  for (; lines > 0 && end > 0; --lines) {
    const size_t nl = text.rfind('\n', end - 1);
    if (nl == std::string::npos) return text;
    end = nl;
  }
  return text.substr(end + (end < text.size() && text[end] == '\n'));
}

// The counts of `STATS <tag> total: voxels=V svo_nodes=N dag_nodes=M`; false when the line is absent.
bool parse_total(const std::string& output, const std::string& tag, PeerCounts& c) {
  const std::string key = "STATS " + tag + " total:";
  const size_t at = output.find(key);
  if (at == std::string::npos) return false;
  unsigned long long v = 0, s = 0, d = 0;
  if (std::sscanf(output.c_str() + at + key.size(), " voxels=%llu svo_nodes=%llu dag_nodes=%llu", &v, &s, &d) != 3)
    return false;
  c = {v, s, d};
  return true;
}

// Everything `fd` delivers until its writer closes it.
std::string read_all(int fd) {
  std::string out;
  char buf[1 << 16];
  for (;;) {
    const ssize_t got = ::read(fd, buf, sizeof buf);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return out;
    out.append(buf, size_t(got));
  }
}

}  // namespace

std::string default_voxcom_path() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ((ec ? std::filesystem::path("build") : exe.parent_path()) / "peers" / "voxcom" / "voxelizer").string();
}

std::string voxcom_mismatch(const BuildOptions& o) {
  if (io::is_vdb(o.input)) return "voxcom reads meshes, not .vdb volumes";
  if (o.voxelize != Voxelizer::Rule::kThin) return "voxcom voxelizes with the thin rule only (--voxelize thin)";
  if (o.placement.origin != GridPlacement::Origin::kMin)
    return "voxcom's grid sits at the mesh's min corner (--grid-origin min)";
  return "";
}

void parse_voxcom_stats(const std::string& output, PeerRun& run) {
  if (!parse_total(output, "svdag", run.svdag) || !parse_total(output, "ssvdag", run.ssvdag))
    throw Error("the peer printed no 'STATS svdag total:' and 'STATS ssvdag total:' lines (is it built by "
                "../shared/peers/voxcom/build.sh, with its stats patch?); its output ends:\n" +
                tail(output, 5));
}

PeerRun run_voxcom(const std::string& binary, const std::string& mesh, uint32_t resolution) {
  ScratchDir dir;
  const std::vector<std::string> args = {binary,   mesh, std::to_string(std::countr_zero(resolution)),
                                         "--out",  dir.file("peer.svo"),
                                         "--svdag", dir.file("peer.svdag"),
                                         "--ussvdag", dir.file("peer.ssvdag")};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // `out` carries the peer's stdout and stderr; `failed` its errno if exec fails (closed by a good exec).
  int out[2], failed[2];
  if (::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(failed, O_CLOEXEC) != 0)
    throw Error(std::string("pipes for the peer: ") + std::strerror(errno));
  PeerRun run;
  const auto start = Clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {  // the child: only async-signal-safe calls until exec
    ::dup2(out[1], STDOUT_FILENO);
    ::dup2(out[1], STDERR_FILENO);
    ::execv(argv[0], argv.data());
    const int e = errno;
    (void)!::write(failed[1], &e, sizeof e);
    ::_exit(127);
  }
  ::close(out[1]);
  ::close(failed[1]);
  if (pid < 0) {
    ::close(out[0]);
    ::close(failed[0]);
    throw Error(std::string("starting the peer: ") + std::strerror(errno));
  }
  const std::string output = read_all(out[0]), exec_error = read_all(failed[0]);
  ::close(out[0]);
  ::close(failed[0]);
  int status = 0;
  struct rusage usage {};
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  if (exec_error.size() == sizeof(int)) {
    int e = 0;
    std::memcpy(&e, exec_error.data(), sizeof e);
    throw Error("the peer " + binary + " cannot be run: " + std::strerror(e));
  }
  run.wall_seconds = since(start);
  run.max_rss_bytes = uint64_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Error("the peer " + binary + " failed (" +
                (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                   : "signal " + std::to_string(WTERMSIG(status))) +
                ") on " + mesh + "; its output ends:\n" + tail(output, 5));
  parse_voxcom_stats(output, run);
  return run;
}

}  // namespace mv::bench

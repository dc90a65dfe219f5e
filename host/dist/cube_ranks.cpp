// The out-of-core build's cubes over MPI ranks: dealt by triangle count, made where they are dealt, and their
// partial DAGs sent to rank 0, which merges them in Morton order as one process would.
#include <sys/resource.h>

#include <climits>
#include <cstring>
#include <stdexcept>

#include "megavox/error.h"
#include "megavox/ranks.h"

#if MEGAVOX_HAVE_MPI
#include <mpi.h>
#endif

namespace mv::dist {

namespace {

constexpr int kPartTag = 1;

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
    if (bytes.size() - at < sizeof(T)) throw Error("a partial DAG from another rank is cut short");
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<uint64_t>();
    if (n > (bytes.size() - at) / sizeof(T)) throw Error("a partial DAG from another rank is cut short");
    std::vector<T> v(n);
    std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
    at += n * sizeof(T);
    return v;
  }
};

uint64_t peak_rss() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return uint64_t(u.ru_maxrss) * 1024;
}

}  // namespace

std::vector<int> deal_cubes(const std::vector<uint64_t>& cube_triangles, int ranks) {
  uint64_t total = 0;
  for (uint64_t t : cube_triangles) total += t;
  std::vector<int> owner(cube_triangles.size(), 0);
  uint64_t before = 0;  // triangles of the cubes before this one
  for (size_t c = 0; c < cube_triangles.size(); ++c) {
    // the rank whose equal share holds this cube's first triangle: contiguous ranges in Morton order
    const uint64_t r = total == 0 ? 0 : static_cast<uint64_t>((unsigned __int128)before * ranks / total);
    owner[c] = static_cast<int>(std::min<uint64_t>(r, ranks - 1));
    before += cube_triangles[c];
  }
  return owner;
}

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
  if (levels != uint64_t{dag.levels} + 1) throw Error("a partial DAG from another rank has a wrong level count");
  dag.level.resize(levels);
  for (DagLevel& l : dag.level) {
    l.mask = in.get_vector<uint32_t>();
    l.first = in.get_vector<uint32_t>();
    l.children = in.get_vector<uint32_t>();
    l.tags = in.get_vector<uint32_t>();
  }
  if (used) *used = in.at;
  else if (in.at != bytes.size()) throw Error("a partial DAG from another rank has bytes past its end");
  return dag;
}

#if MEGAVOX_HAVE_MPI

struct CubeRanks::Pending {
  std::vector<uint8_t> bytes;
  MPI_Request request = MPI_REQUEST_NULL;
};

CubeRanks::CubeRanks(const World& w) : world_(w) {
  ranks_.writes = w.rank == 0;
  ranks_.exchange = [this](const std::vector<uint64_t>& cube_triangles) {
    owner_ = deal_cubes(cube_triangles, world_.size);
    for (size_t c = 0; c < owner_.size(); ++c)
      if (owner_[c] == world_.rank) report.cubes += 1, report.triangles += cube_triangles[c];
    CubeExchange ex;
    ex.merges = world_.rank == 0;
    ex.mine = [this](uint64_t c) { return owner_.at(c) == world_.rank; };
    ex.send = [this](uint64_t, const Dag* part, std::vector<uint8_t> payload) {
      auto* p = new Pending;
      pending_.push_back(p);
      if (part) {  // the part, then the payload after it
        p->bytes = pack_dag(*part);
        p->bytes.insert(p->bytes.end(), payload.begin(), payload.end());
      }
      if (p->bytes.size() > size_t{INT_MAX})
        throw Error("a cube's partial DAG is over 2 GiB: use a smaller --cube");
      report.bytes_exchanged += p->bytes.size();
      MPI_Isend(p->bytes.data(), static_cast<int>(p->bytes.size()), MPI_BYTE, 0, kPartTag, MPI_COMM_WORLD, &p->request);
    };
    ex.receive = [this](uint64_t c, std::vector<uint8_t>& payload) -> std::optional<Dag> {
      MPI_Status status;
      MPI_Probe(owner_.at(c), kPartTag, MPI_COMM_WORLD, &status);
      int n = 0;
      MPI_Get_count(&status, MPI_BYTE, &n);
      std::vector<uint8_t> bytes(static_cast<size_t>(n));
      MPI_Recv(bytes.data(), n, MPI_BYTE, owner_.at(c), kPartTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      report.bytes_exchanged += bytes.size();
      if (bytes.empty()) return std::nullopt;
      size_t used = 0;
      Dag part = unpack_dag(bytes, &used);
      payload.assign(bytes.begin() + static_cast<std::ptrdiff_t>(used), bytes.end());
      return part;
    };
    return ex;
  };
}

void CubeRanks::finish() {
  for (Pending* p : pending_) MPI_Wait(&p->request, MPI_STATUS_IGNORE);
  for (Pending* p : pending_) delete p;
  pending_.clear();
}

CubeRanks::~CubeRanks() {
  for (Pending* p : pending_) delete p;  // after an error: the run is being aborted
}

std::vector<RankReport> gather_reports(const RankReport& mine) {
  RankReport me = mine;
  me.peak_memory_bytes = peak_rss();
  const World& w = world();
  std::vector<RankReport> all(w.rank == 0 ? size_t(w.size) : 0);
  MPI_Gather(&me, sizeof me, MPI_BYTE, all.data(), sizeof me, MPI_BYTE, 0, MPI_COMM_WORLD);
  return all;
}

#else

struct CubeRanks::Pending {};
CubeRanks::CubeRanks(const World& w) : world_(w) {}
void CubeRanks::finish() {}
CubeRanks::~CubeRanks() = default;
std::vector<RankReport> gather_reports(const RankReport& mine) {
  RankReport me = mine;
  me.peak_memory_bytes = peak_rss();
  return {me};
}

#endif

}  // namespace mv::dist

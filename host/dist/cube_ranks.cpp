// The out-of-core build's cubes over MPI ranks: dealt by voxel estimate and made where they are dealt. A
// reduced build merges them over the ranks (dag/merge_over_ranks.h) and sends only their colours to rank 0;
// the plain octree sends the partial DAGs to rank 0, which merges them in Morton order as one process would.
#include <sys/resource.h>

#include <chrono>
#include <climits>
#include <thread>
#include <cstring>
#include <stdexcept>

#include "io/cube_parts.h"
#include "megavox/error.h"
#include "megavox/rank_collectives.h"
#include "megavox/ranks.h"

#if MEGAVOX_HAVE_MPI
#include <mpi.h>
#endif

namespace mv::dist {

namespace {

constexpr int kPartTag = 1;

uint64_t peak_rss() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return uint64_t(u.ru_maxrss) * 1024;
}

}  // namespace

#if MEGAVOX_HAVE_MPI

struct CubeRanks::Pending {
  std::vector<uint8_t> bytes;
  MPI_Request request = MPI_REQUEST_NULL;
};

CubeRanks::CubeRanks(const World& w) : world_(w), collectives_(collectives(w)) {
  ranks_.writes = w.rank == 0;
  ranks_.collectives = &collectives_;
  ranks_.exchange = [this](const std::vector<uint64_t>& cube_voxels) {
    owner_ = deal_in_order(cube_voxels, world_.size);
    for (size_t c = 0; c < owner_.size(); ++c)
      if (owner_[c] == world_.rank) report.cubes += 1, report.voxel_estimate += cube_voxels[c];
    CubeExchange ex;
    ex.merges = world_.rank == 0;
    ex.mine = [this](uint64_t c) { return owner_.at(c) == world_.rank; };
    ex.send = [this](uint64_t, const Dag* part, std::vector<uint8_t> payload) {
      auto* p = new Pending;
      pending_.push_back(p);
      if (part) {  // the part, then the payload after it
        p->bytes = io::pack_dag(*part);
        p->bytes.insert(p->bytes.end(), payload.begin(), payload.end());
      }
      if (p->bytes.size() > size_t{INT_MAX})
        throw Error("a cube's partial DAG is over 2 GiB: use a smaller --cube");
      report.bytes_exchanged += p->bytes.size();
      MPI_Isend(p->bytes.data(), static_cast<int>(p->bytes.size()), MPI_BYTE, 0, kPartTag, MPI_COMM_WORLD, &p->request);
    };
    // A reduced build merges over the ranks: only the cubes' colours travel, to rank 0.
    ex.collectives = &collectives_;
    ex.bytes_exchanged = &report.bytes_exchanged;
    ex.send_payload = [this](uint64_t, std::vector<uint8_t> payload) {
      auto* p = new Pending;
      pending_.push_back(p);
      p->bytes = std::move(payload);
      if (p->bytes.size() > size_t{INT_MAX}) throw Error("a cube's colours are over 2 GiB: use a smaller --cube");
      report.bytes_exchanged += p->bytes.size();
      MPI_Isend(p->bytes.data(), static_cast<int>(p->bytes.size()), MPI_BYTE, 0, kPartTag, MPI_COMM_WORLD, &p->request);
    };
    ex.receive_payload = [this](uint64_t c, std::vector<uint8_t>& payload) { payload = receive_from(owner_.at(c)); };
    ex.receive = [this](uint64_t c, std::vector<uint8_t>& payload) -> std::optional<Dag> {
      std::vector<uint8_t> bytes = receive_from(owner_.at(c));
      if (bytes.empty()) return std::nullopt;
      size_t used = 0;
      Dag part = io::unpack_dag(bytes, &used);
      payload.assign(bytes.begin() + static_cast<std::ptrdiff_t>(used), bytes.end());
      return part;
    };
    return ex;
  };
}

std::vector<uint8_t> CubeRanks::receive_from(int rank) {
  MPI_Status status;
  MPI_Probe(rank, kPartTag, MPI_COMM_WORLD, &status);
  int n = 0;
  MPI_Get_count(&status, MPI_BYTE, &n);
  std::vector<uint8_t> bytes(static_cast<size_t>(n));
  MPI_Recv(bytes.data(), n, MPI_BYTE, rank, kPartTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  report.bytes_exchanged += bytes.size();
  return bytes;
}

void CubeRanks::finish() {
  for (Pending* p : pending_) MPI_Wait(&p->request, MPI_STATUS_IGNORE);
  for (Pending* p : pending_) delete p;
  pending_.clear();
}

CubeRanks::~CubeRanks() {
  for (Pending* p : pending_) delete p;  // after an error: the run is being aborted
}

std::vector<int> ranks_failing(bool ok) {
  const World& w = world();
  std::vector<int> all(static_cast<size_t>(w.size));
  int mine = ok ? 1 : 0;
  MPI_Allgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> failing;
  for (int r = 0; r < w.size; ++r)
    if (!all[static_cast<size_t>(r)]) failing.push_back(r);
  return failing;
}

std::vector<RankReport> gather_reports(const RankReport& mine) {
  RankReport me = mine;
  me.peak_memory_bytes = peak_rss();
  const World& w = world();
  std::vector<RankReport> all(w.rank == 0 ? size_t(w.size) : 0);
  // The other ranks wait here while rank 0 finishes alone (a point build's join and write): asleep, so that
  // their cores are rank 0's (Open MPI's blocking wait polls).
  MPI_Request request;
  MPI_Igather(&me, sizeof me, MPI_BYTE, all.data(), sizeof me, MPI_BYTE, 0, MPI_COMM_WORLD, &request);
  for (int done = 0; MPI_Test(&request, &done, MPI_STATUS_IGNORE), !done;)
    if (w.rank != 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return all;
}

#else

struct CubeRanks::Pending {};
CubeRanks::CubeRanks(const World& w) : world_(w) {}
std::vector<int> ranks_failing(bool) { return {}; }
void CubeRanks::finish() {}
CubeRanks::~CubeRanks() = default;
std::vector<RankReport> gather_reports(const RankReport& mine) {
  RankReport me = mine;
  me.peak_memory_bytes = peak_rss();
  return {me};
}

#endif

}  // namespace mv::dist

// megavox — one run over several processes (MPI ranks, `mpirun -np N megavox build ...`): who this process is,
// the node's share of budgets and threads, and the out-of-core build's cube exchange (docs/distributed.md).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/build.h"
#include "megavox/rank_collectives.h"

namespace mv::dist {

struct World {
  int rank = 0, size = 1;              // MPI_COMM_WORLD
  int local_rank = 0, local_size = 1;  // the ranks on this node (MPI_COMM_TYPE_SHARED)
};

// Starts MPI when mpirun launched this process (OMPI_COMM_WORLD_SIZE is set) and megavox was built with it;
// otherwise the world of one process, MPI untouched: Open MPI's singleton start would spawn a daemon that
// listens on every interface. Idle waits yield the core (mpi_yield_when_idle) unless the user set it. With
// more than one rank on the node, the default host memory budget, device memory budget and worker threads
// (TBB, PoCL, lavapipe) are divided among them.
const World& start(int* argc, char*** argv);
const World& world();
// Lifts this rank's share of the node's worker threads (TBB): for rank 0 once the others only wait for it.
void take_node_threads();
// MPI_Finalize, after a run that started MPI.
void stop();
// Ends every rank (MPI_Abort) with `code`, after this rank printed why; returns only without MPI.
void abort_all(int code);
// "Open MPI v4.1.4" (what --version says), or "not built in".
std::string mpi_summary();

// What one rank did in a distributed build, gathered on rank 0 for --json.
struct RankReport {
  double seconds = 0;
  uint64_t voxels = 0;           // in the cubes it made
  uint64_t points = 0;           // a point build: in the cells dealt to it, whose subtrees it built
  uint64_t points_read = 0;      // a point build: its slice of the input
  uint64_t tiles = 0;            // a point build to 3D Tiles: the tiles it wrote
  uint64_t cubes = 0;            // cubes it owned
  uint64_t voxel_estimate = 0;   // of those cubes, as they were dealt
  uint64_t bytes_read = 0;       // of the input
  uint64_t bytes_exchanged = 0;  // sent and received
  uint64_t peak_memory_bytes = 0;
};

// The build's side of the exchange (BuildOptions::ranks): cubes dealt to ranks in contiguous Morton ranges of
// equal voxel estimates; a reduced build's merge over the ranks (the collectives), and what travels to rank 0
// as it is made (non-blocking), received there in Morton order: the cubes' colours, or the plain octree's
// partial DAGs. `report` collects this rank's counts. Lives as long as the build.
class CubeRanks {
 public:
  explicit CubeRanks(const World& w);
  ~CubeRanks();
  CubeRanks(const CubeRanks&) = delete;
  CubeRanks& operator=(const CubeRanks&) = delete;
  const BuildRanks& build_ranks() const { return ranks_; }
  // Waits for every send to complete (before the process may end).
  void finish();
  RankReport report;

 private:
  struct Pending;
  std::vector<uint8_t> receive_from(int rank);  // the next message of a cube from `rank`
  World world_;
  RankCollectives collectives_;
  BuildRanks ranks_;
  std::vector<int> owner_;
  std::vector<Pending*> pending_;
};

// The collectives a point build over ranks uses (megavox/rank_collectives.h), over MPI_COMM_WORLD.
RankCollectives collectives(const World& w);

// Collective: the ranks whose `ok` is false, in rank order, on every rank (empty without MPI).
std::vector<int> ranks_failing(bool ok);

// Every rank's report at rank 0 (the others get an empty list); a collective call.
std::vector<RankReport> gather_reports(const RankReport& mine);



}  // namespace mv::dist

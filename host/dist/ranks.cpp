// Starting and ending a run over MPI ranks, and the node's share of budgets and threads.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>

#include <tbb/global_control.h>

#include "megavox/ranks.h"

#if MEGAVOX_HAVE_MPI
#include <mpi.h>
#endif

namespace mv::dist {

namespace {

World g_world;
bool g_started = false;
std::unique_ptr<tbb::global_control> g_threads;

// Divides what one process would take of this node among its `ranks`: budgets and worker threads.
void share_node(int ranks) {
  if (ranks <= 1) return;
  set_host_memory_share(static_cast<uint32_t>(ranks));
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::string threads = std::to_string(std::max(1u, cores / static_cast<unsigned>(ranks)));
  g_threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    std::max<size_t>(1, cores / ranks));
  setenv("POCL_MAX_PTHREAD_COUNT", threads.c_str(), 0);  // PoCL's worker threads
  setenv("LP_NUM_THREADS", threads.c_str(), 0);          // lavapipe's
}

}  // namespace

const World& world() { return g_world; }

void take_node_threads() {
  if (!g_threads) return;
  g_threads.reset();  // TBB's default again: every core of the node
}

#if MEGAVOX_HAVE_MPI

const World& start(int* argc, char*** argv) {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!size || !*size || g_started) return g_world;
  setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);  // a waiting rank gives its core to the others
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_world.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_world.size);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, g_world.rank, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &g_world.local_rank);
  MPI_Comm_size(node, &g_world.local_size);
  MPI_Comm_free(&node);
  share_node(g_world.local_size);
  return g_world;
}

void stop() {
  if (!g_started) return;
  g_started = false;
  MPI_Finalize();
}

void abort_all(int code) {
  if (g_started && g_world.size > 1) {
    std::fflush(stdout);
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
  }
}

std::string mpi_summary() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int n = 0;
  MPI_Get_library_version(text, &n);
  std::string s(text, static_cast<size_t>(n));
  s = s.substr(0, s.find_first_of(",\n"));
  return s + " (run with mpirun -np N)";
}

#else

const World& start(int*, char***) { return g_world; }
void stop() {}
void abort_all(int) {}
std::string mpi_summary() { return "not built in (install libopenmpi-dev and rebuild)"; }

#endif

}  // namespace mv::dist

// The collectives of megavox/rank_collectives.h over MPI_COMM_WORLD: buffers of any size, sent in pieces of at
// most 1 GiB (MPI counts are ints); messages between two ranks arrive in the order they were sent.
#include <algorithm>
#include <chrono>
#include <climits>
#include <thread>
#include <vector>

#include "megavox/error.h"
#include "megavox/ranks.h"

#if MEGAVOX_HAVE_MPI
#include <mpi.h>
#endif

namespace mv::dist {

#if MEGAVOX_HAVE_MPI

namespace {

constexpr int kCollectiveTag = 2;
constexpr uint64_t kPiece = uint64_t{1} << 30;

void post_send(const std::vector<uint8_t>& bytes, int to, std::vector<MPI_Request>& requests) {
  for (uint64_t at = 0; at < bytes.size(); at += kPiece) {
    requests.emplace_back();
    MPI_Isend(bytes.data() + at, static_cast<int>(std::min<uint64_t>(kPiece, bytes.size() - at)), MPI_BYTE, to,
              kCollectiveTag, MPI_COMM_WORLD, &requests.back());
  }
}

void post_receive(std::vector<uint8_t>& bytes, int from, std::vector<MPI_Request>& requests) {
  for (uint64_t at = 0; at < bytes.size(); at += kPiece) {
    requests.emplace_back();
    MPI_Irecv(bytes.data() + at, static_cast<int>(std::min<uint64_t>(kPiece, bytes.size() - at)), MPI_BYTE, from,
              kCollectiveTag, MPI_COMM_WORLD, &requests.back());
  }
}

// Waits for every request without holding a core: a rank that waits for another's work (rank 0 writing the
// output while the others hand it their points) would otherwise take a core from it, since Open MPI's blocking
// waits poll. A short spin keeps quick exchanges quick; then the rank sleeps between tests, up to 1 ms.
void wait_all(std::vector<MPI_Request>& requests) {
  if (requests.empty()) return;
  int done = 0;
  for (int spins = 0; MPI_Testall(static_cast<int>(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE),
           !done;
       ++spins)
    if (spins >= 64) std::this_thread::sleep_for(std::chrono::microseconds(std::min(1000, 10 * (spins - 63))));
}

void wait_one(MPI_Request& request) {
  std::vector<MPI_Request> one{request};
  wait_all(one);
}

// Every other rank r gets `to(r)` and sends sizes[r] bytes here; this rank's own entry stays empty.
template <class To>
RankBytes exchange(const World& w, const To& to, const std::vector<uint64_t>& sizes) {
  RankBytes got(static_cast<size_t>(w.size));
  std::vector<MPI_Request> requests;
  for (int r = 0; r < w.size; ++r) {
    if (r == w.rank) continue;
    got[static_cast<size_t>(r)].resize(sizes[static_cast<size_t>(r)]);
    post_receive(got[static_cast<size_t>(r)], r, requests);
    post_send(to(r), r, requests);
  }
  wait_all(requests);
  return got;
}

}  // namespace

RankCollectives collectives(const World& w) {
  RankCollectives c;
  c.rank = w.rank;
  c.size = w.size;
  c.lead_alone = take_node_threads;
  c.sleepy_barrier = [] {
    MPI_Request request;
    MPI_Ibarrier(MPI_COMM_WORLD, &request);
    for (int done = 0; MPI_Test(&request, &done, MPI_STATUS_IGNORE), !done;)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
  c.all_gather = [w](const std::vector<uint8_t>& mine) {
    uint64_t size = mine.size();
    std::vector<uint64_t> sizes(static_cast<size_t>(w.size));
    MPI_Request request;
    MPI_Iallgather(&size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD, &request);
    wait_one(request);
    RankBytes all = exchange(w, [&](int) -> const std::vector<uint8_t>& { return mine; }, sizes);
    all[static_cast<size_t>(w.rank)] = mine;
    return all;
  };
  c.all_to_all = [w](RankBytes&& parts) {
    std::vector<uint64_t> out(static_cast<size_t>(w.size)), in(static_cast<size_t>(w.size));
    for (int r = 0; r < w.size; ++r) out[static_cast<size_t>(r)] = parts[static_cast<size_t>(r)].size();
    MPI_Request request;
    MPI_Ialltoall(out.data(), 1, MPI_UINT64_T, in.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD, &request);
    wait_one(request);
    RankBytes got = exchange(w, [&](int r) -> const std::vector<uint8_t>& { return parts[static_cast<size_t>(r)]; }, in);
    got[static_cast<size_t>(w.rank)] = std::move(parts[static_cast<size_t>(w.rank)]);
    return got;
  };
  c.gather = [w](std::vector<uint8_t>&& mine) {
    uint64_t size = mine.size();
    std::vector<uint64_t> sizes(static_cast<size_t>(w.size));
    MPI_Request request;
    MPI_Igather(&size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request);
    wait_one(request);
    RankBytes all;
    std::vector<MPI_Request> requests;
    if (w.rank == 0) {
      all.resize(static_cast<size_t>(w.size));
      for (int r = 1; r < w.size; ++r) {
        all[static_cast<size_t>(r)].resize(sizes[static_cast<size_t>(r)]);
        post_receive(all[static_cast<size_t>(r)], r, requests);
      }
      all[0] = std::move(mine);
    } else {
      post_send(mine, 0, requests);
    }
    wait_all(requests);
    return all;
  };
  return c;
}

#else

RankCollectives collectives(const World& w) {
  RankCollectives c;
  c.rank = w.rank;
  c.size = w.size;
  c.all_gather = [](const std::vector<uint8_t>& mine) { return RankBytes{mine}; };
  c.all_to_all = [](RankBytes&& parts) { return std::move(parts); };
  c.gather = [](std::vector<uint8_t>&& mine) { return RankBytes{std::move(mine)}; };
  return c;
}

#endif

}  // namespace mv::dist

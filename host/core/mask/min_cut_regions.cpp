// The host side of the region Boykov-Kolmogorov min-cut (kernels/common/min_cut_regions.h): the terminals cancel on
// the host, the regions run side by side until each is done, then each level merges 2 x 2 of them and goes on
// from their trees while a level keeps enough regions to fill the device; the terminals left are handed back for
// push-relabel to finish. A first level of one region ends on its own: the pixels in the sink's tree are those
// that can reach the sink.
#include "min_cut_regions.h"

#include <algorithm>
#include <string>

#include "common/min_cut_regions.h"
#include "megavox/error.h"

namespace mv::mask {

namespace {

// Runs the kernel until every item of the level is done. Each dispatch gives an item p.budget steps; the state
// words say where each stopped.
uint32_t run_level(Device& dev, Kernel& k, const MvMinCutRegionsParams& p, uint32_t items, uint32_t local, Buffer& sb,
                   std::vector<uint32_t>& state, std::initializer_list<const Buffer*> buffers, uint64_t max_dispatches) {
  uint32_t dispatches = 0;
  for (;;) {
    if (++dispatches > max_dispatches)
      throw Error("min-cut: no convergence after " + std::to_string(max_dispatches) + " dispatches");
    dev.fill(sb, 0, 4, uint64_t{items} * MV_BK_STATE_WORDS * 4);  // the next region to take
    dev.barrier();
    dev.dispatch(k, (items + local - 1) / local, local, buffers, p);
    dev.barrier();
    dev.download(sb, state.data(), uint64_t{items} * MV_BK_STATE_WORDS * 4);
    bool done = true;
    for (uint32_t r = 0; r < items; ++r) done = done && state[r * MV_BK_STATE_WORDS + MV_BK_W_STEP] == MV_BK_DONE;
    if (done) return dispatches;
  }
}

// A region's state before its first step: `first` (MV_BK_START or MV_BK_SEAMS), nothing queued.
void start_state(uint32_t* words, uint32_t first, uint32_t time) {
  std::fill(words, words + MV_BK_STATE_WORDS, 0u);
  words[MV_BK_W_STEP] = first;
  words[MV_BK_W_CUR] = words[MV_BK_W_HEAD] = words[MV_BK_W_TAIL] = MV_BK_NONE;
  words[MV_BK_W_TIME] = time;
}

}  // namespace

uint64_t min_cut_regions(Device& dev, const GridGraph& g, uint32_t regions, uint32_t least, Buffer& rb,
                         std::vector<uint32_t>& excess, std::vector<uint32_t>& sink, std::vector<uint8_t>& reaches,
                         MinCutStats& st, bool& finished) {
  const uint64_t n = uint64_t{g.width} * g.height;
  const uint32_t conn = g.connectivity;
  uint64_t flow = 0;
  std::vector<uint32_t> term(n);
  for (uint64_t i = 0; i < n; ++i) {  // a pixel's two terminal edges cancel (that flow reaches the sink): the rest, signed
    flow += std::min(excess[i], sink[i]);
    term[i] = static_cast<uint32_t>(static_cast<int32_t>(excess[i]) - static_cast<int32_t>(sink[i]));
  }
  MvMinCutRegionsParams p{};
  p.width = g.width;
  p.height = g.height;
  p.conn = conn;
  // Regions at least 2 pixels wide and high, so the seams between them are two distinct lines.
  p.regions_x = std::clamp<uint32_t>(regions, 1, std::max<uint32_t>(g.width / 2, 1));
  p.regions_y = std::clamp<uint32_t>(regions, 1, std::max<uint32_t>(g.height / 2, 1));
  const uint32_t max_loop = dev.info().max_loop_iterations;
  // Under a loop cap, which counts the iterations of all of an invocation's loops together, a step's loop over a
  // pixel's edges or along a walk counts with the step. On lavapipe (cap 65,535) a dispatch of 3,500 steps with
  // 8-pixel walks stayed under it in GrabCut's cuts and one of 5,000 did not: the budget (1,820) keeps a margin.
  p.walk = max_loop != 0 ? 8 : (1u << 20);
  p.budget = max_loop != 0 ? max_loop / (4 * (std::max(conn, p.walk) + 1)) : (1u << 26);
  const uint32_t items = p.regions_x * p.regions_y;
  // One item per region, in work-groups as wide as the device likes (lavapipe: 8 lanes of one SIMD thread, 10x the
  // steps per second of one region a group).
  const uint32_t local = std::clamp<uint32_t>(dev.info().preferred_work_group_size, 1, std::max<uint32_t>(items, 1));
  // Under a loop cap, lanes of one group diverging across the steps run more iterations together than each alone:
  // on lavapipe 1,820 steps a lane in 8-wide groups never finished a 481 x 321 8-connected cut (9 minutes), a
  // quarter of that finished it in 2.8 s.
  if (max_loop != 0 && local > 1) p.budget /= 4;

  Buffer tb = dev.alloc(n * 4, "min-cut terminal capacities");
  Buffer nodeb = dev.alloc(n * MV_BK_NODE_WORDS * 4, "min-cut search trees");
  Buffer ob = dev.alloc(n * 4, "min-cut orphans");
  Buffer sb = dev.alloc(uint64_t{items} * MV_BK_STATE_WORDS * 4 + 4, "min-cut region states");
  dev.upload(tb, term.data(), n * 4);
  Buffer nb = dev.alloc(n * 4, "min-cut active queue");  // nodeb and nb: the first level's start step sets them
  std::vector<uint32_t> state(uint64_t{items} * MV_BK_STATE_WORDS);
  for (uint32_t r = 0; r < items; ++r) start_state(&state[r * MV_BK_STATE_WORDS], MV_BK_START, 0);
  dev.upload(sb, state.data(), state.size() * 4);
  Kernel& k = dev.kernel(KernelId::min_cut_regions);
  const std::initializer_list<const Buffer*> buffers = {&rb, &tb, &nodeb, &nb, &ob, &sb};
  // Each augmentation moves at least one unit of flow in a bounded number of steps, so a working device ends
  // long before this; the guard catches a broken one.
  const uint64_t guard = uint64_t{1} << 30;
  st.rounds = 0;
  for (p.group = 1;; p.group *= 2) {  // each level merges 2 x 2 regions of the one before, up to the whole grid
    const uint32_t level =
        mv_bk_level_regions(p.regions_x, p.group) * mv_bk_level_regions(p.regions_y, p.group);
    st.rounds += run_level(dev, k, p, level, local, sb, state, buffers, guard);
    uint32_t time = 0;
    for (uint32_t r = 0; r < level; ++r) {
      flow += state[r * MV_BK_STATE_WORDS + MV_BK_W_FLOW];
      time = std::max(time, state[r * MV_BK_STATE_WORDS + MV_BK_W_TIME]);
    }
    if (level == 1) break;
    // The next level's regions go on from their parts' trees, with stamps above every part's; a level of fewer
    // than `least` regions is left to push-relabel, which keeps the whole device busy.
    const uint32_t next = mv_bk_level_regions(p.regions_x, p.group * 2) * mv_bk_level_regions(p.regions_y, p.group * 2);
    if (next < least) {
      finished = false;
      // What the regions left on the terminals, for push-relabel: the source's part as excess, the sink's apart.
      dev.download(tb, term.data(), n * 4);
      for (uint64_t i = 0; i < n; ++i) {
        const int32_t t = static_cast<int32_t>(term[i]);
        excess[i] = t > 0 ? static_cast<uint32_t>(t) : 0u;
        sink[i] = t < 0 ? static_cast<uint32_t>(-int64_t{t}) : 0u;
      }
      return flow;
    }
    for (uint32_t r = 0; r < next; ++r) start_state(&state[r * MV_BK_STATE_WORDS], MV_BK_SEAMS, time + 1);
    dev.upload(sb, state.data(), uint64_t{next} * MV_BK_STATE_WORDS * 4);
  }
  finished = true;
  // The trees where the device keeps them in host memory (CPU devices), else a copy.
  std::vector<uint32_t> copy;
  const auto* node = static_cast<const uint32_t*>(dev.host_view(nodeb));
  if (node) {
    dev.finish();
  } else {
    copy.resize(n * MV_BK_NODE_WORDS);
    dev.download(nodeb, copy.data(), copy.size() * 4);
    node = copy.data();
  }
  for (uint64_t i = 0; i < n; ++i) {
    const uint32_t tree = node[MV_BK_TREE(i)];
    reaches[i] = (tree & 15u) != MV_BK_FREE && (tree & MV_BK_SINK) != 0 ? 1 : 0;
  }
  return flow;
}

}  // namespace mv::mask

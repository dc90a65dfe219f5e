// The out-of-core merge's levels reduced over ranks (merge_over_ranks.h).
#include "merge_over_ranks.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

#include "megavox/error.h"
#include "megavox/rank_message.h"

namespace mv::detail {

namespace {

constexpr uint32_t kSamples = 64;  // keys each rank offers for the splitters
constexpr uint32_t kMaxSeed = 16;  // as the one-process reduction: 64-bit hashes that collide this often are a bug

RankBytes all_gather(RankMerge& m, std::vector<uint8_t> mine) {
  m.bytes_exchanged += mine.size() * static_cast<uint64_t>(m.ranks.size - 1);
  RankBytes all = m.ranks.all_gather(mine);
  m.bytes_exchanged += bytes_of_others(all, m.ranks.rank);
  return all;
}

RankBytes all_to_all(RankMerge& m, RankBytes parts) {
  m.bytes_exchanged += bytes_of_others(parts, m.ranks.rank);
  RankBytes got = m.ranks.all_to_all(std::move(parts));
  m.bytes_exchanged += bytes_of_others(got, m.ranks.rank);
  return got;
}

// Level 1: a class is a (canonical) 8-bit mask, numbered by rank among the masks present on any rank.
Reduced leaf_classes(Device& dev, const SvoLevel& lv, const Reduction& red, RankMerge& m, DagLevel& level) {
  std::vector<uint8_t> present(256, 0);
  if (lv.n) {
    Reduced mine = reduce_level(dev, lv, Reduced(), true, red);
    std::vector<uint32_t> rank(257);
    dev.download(mine.class_rank, rank.data(), 257 * 4);
    for (uint32_t c = 0; c < 256; ++c) present[c] = rank[c + 1] > rank[c];
  }
  std::vector<uint32_t> rank(257, 0), masks;
  for (const std::vector<uint8_t>& theirs : all_gather(m, present))
    for (uint32_t c = 0; c < 256; ++c) present[c] |= theirs.at(c);
  for (uint32_t c = 0; c < 256; ++c) {
    rank[c + 1] = rank[c] + present[c];
    if (present[c]) masks.push_back(c);
  }
  Reduced r;
  r.distinct = static_cast<uint32_t>(masks.size());
  r.class_rank = dev.alloc(257 * 4, "leaf classes");
  dev.upload(r.class_rank, rank.data(), 257 * 4);
  r.class_mask = dev.alloc(uint64_t{std::max<uint32_t>(r.distinct, 1)} * 4, "leaf class masks");
  if (r.distinct) dev.upload(r.class_mask, masks.data(), uint64_t{r.distinct} * 4);
  if (m.ranks.rank == 0) level.mask = std::move(masks);
  return r;
}

// N - 1 keys that cut every rank's classes into N ranges of about equal counts: each rank offers its count and
// up to kSamples of its (sorted) keys, evenly spaced, each standing for its share of that count.
std::vector<uint64_t> splitters(const std::vector<uint64_t>& keys, RankMerge& m) {
  MessageWriter w;
  w.put<uint64_t>(keys.size());
  std::vector<uint64_t> samples;
  const uint64_t s = std::min<uint64_t>(keys.size(), kSamples);
  for (uint64_t i = 0; i < s; ++i) samples.push_back(keys[(2 * i + 1) * keys.size() / (2 * s)]);
  w.put_all(samples);
  std::vector<std::pair<uint64_t, double>> weighted;
  double total = 0;
  for (const std::vector<uint8_t>& b : all_gather(m, std::move(w.bytes))) {
    MessageReader in(b);
    const auto count = in.get<uint64_t>();
    in.get_all(samples);
    total += double(count);
    for (uint64_t k : samples) weighted.emplace_back(k, double(count) / double(samples.size()));
  }
  std::sort(weighted.begin(), weighted.end());
  std::vector<uint64_t> cut;
  double sum = 0;
  for (const auto& [key, weight] : weighted) {
    sum += weight;
    while (cut.size() + 1 < size_t(m.ranks.size) && sum >= total * double(cut.size() + 1) / m.ranks.size)
      cut.push_back(key);
  }
  while (cut.size() + 1 < size_t(m.ranks.size)) cut.push_back(UINT64_MAX);
  return cut;
}

int owner_of(const std::vector<uint64_t>& cut, uint64_t key) {
  return static_cast<int>(std::upper_bound(cut.begin(), cut.end(), key) - cut.begin());
}

// A class as it travels: its stored mask, then its children's ids and, with symmetry, their tags (a byte each).
void put_class(MessageWriter& w, const DagLevel& l, size_t c, bool symmetric) {
  const uint32_t k = static_cast<uint32_t>(std::popcount(l.mask[c]));
  w.put(l.mask[c]);
  const auto* ids = reinterpret_cast<const uint8_t*>(&l.children[l.first[c]]);
  w.bytes.insert(w.bytes.end(), ids, ids + 4 * k);
  if (symmetric)
    for (uint32_t j = 0; j < k; ++j) w.put(static_cast<uint8_t>(l.tags[l.first[c] + j]));
}

// The bytes of one travelling class starting at `at` (checked against `end`).
size_t class_bytes(const uint8_t* at, const uint8_t* end, bool symmetric) {
  if (end - at < 4) throw Error("internal error: a DAG class from another rank is cut short");
  uint32_t mask = 0;
  std::memcpy(&mask, at, 4);
  const size_t n = 4 + size_t(std::popcount(mask)) * (symmetric ? 5 : 4);
  if (size_t(end - at) < n) throw Error("internal error: a DAG class from another rank is cut short");
  return n;
}

void append_class(DagLevel& l, const uint8_t* at, bool symmetric) {
  uint32_t mask = 0;
  std::memcpy(&mask, at, 4);
  const uint32_t k = static_cast<uint32_t>(std::popcount(mask));
  l.mask.push_back(mask);
  l.first.push_back(static_cast<uint32_t>(l.children.size()));
  const size_t from = l.children.size();
  l.children.resize(from + k);
  std::memcpy(&l.children[from], at + 4, 4 * size_t{k});
  if (symmetric)
    for (uint32_t j = 0; j < k; ++j) l.tags.push_back(at[4 + 4 * k + j]);
}

struct Numbered {
  std::vector<uint32_t> id;  // of each of this rank's classes, over every rank's
  uint32_t distinct = 0;     // over every rank
  bool collided = false;     // two different classes share a key (a hash seed that failed on no one rank)
};

// Collective: this rank's classes (`keys`, sorted, and `mine`, the level they assemble) numbered over every
// rank's; rank 0 gets the whole level in `level` unless two keys collided.
Numbered number_classes(const std::vector<uint64_t>& keys, const DagLevel& mine, bool symmetric, RankMerge& m,
                        DagLevel& level) {
  const auto ranks = static_cast<size_t>(m.ranks.size);
  const std::vector<uint64_t> cut = splitters(keys, m);
  std::vector<MessageWriter> out(ranks);
  for (size_t c = 0; c < keys.size(); ++c) {
    MessageWriter& w = out[static_cast<size_t>(owner_of(cut, keys[c]))];
    w.put(keys[c]);
    put_class(w, mine, c, symmetric);
  }
  RankBytes parts(ranks);
  for (size_t r = 0; r < ranks; ++r) parts[r] = std::move(out[r].bytes);
  const RankBytes got = all_to_all(m, std::move(parts));

  // The owner's share: every rank's classes in its key range, sorted by key; equal keys must be equal classes.
  struct Item {
    uint64_t key;
    const uint8_t* bytes;
    uint32_t size, src, index;
  };
  std::vector<Item> items;
  std::vector<std::vector<uint32_t>> reply(ranks);
  for (size_t src = 0; src < ranks; ++src) {
    const uint8_t* at = got[src].data();
    const uint8_t* end = at + got[src].size();
    while (at < end) {
      if (end - at < 8) throw Error("internal error: a DAG class from another rank is cut short");
      Item it{};
      std::memcpy(&it.key, at, 8);
      it.bytes = at + 8;
      it.size = static_cast<uint32_t>(class_bytes(it.bytes, end, symmetric));
      it.src = static_cast<uint32_t>(src);
      it.index = static_cast<uint32_t>(reply[src].size());
      reply[src].push_back(0);
      items.push_back(it);
      at = it.bytes + it.size;
    }
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return a.key != b.key ? a.key < b.key : a.src != b.src ? a.src < b.src : a.index < b.index;
  });
  Numbered nb;
  std::vector<const Item*> distinct;
  for (const Item& it : items) {
    if (distinct.empty() || distinct.back()->key != it.key) {
      distinct.push_back(&it);
    } else if (distinct.back()->size != it.size || std::memcmp(distinct.back()->bytes, it.bytes, it.size) != 0) {
      nb.collided = true;
    }
    reply[it.src][it.index] = static_cast<uint32_t>(distinct.size() - 1);
  }
  MessageWriter counts;
  counts.put<uint64_t>(distinct.size());
  counts.put<uint8_t>(nb.collided);
  uint64_t offset = 0, total = 0;
  const RankBytes all = all_gather(m, std::move(counts.bytes));
  for (size_t r = 0; r < ranks; ++r) {
    MessageReader in(all[r]);
    const auto n = in.get<uint64_t>();
    if (in.get<uint8_t>()) nb.collided = true;
    if (int(r) < m.ranks.rank) offset += n;
    total += n;
  }
  if (total >= UINT32_MAX) throw Error("out-of-core build: more than 2^32 distinct nodes in one level");
  nb.distinct = static_cast<uint32_t>(total);
  if (nb.collided) return nb;

  RankBytes ids(ranks);
  for (size_t r = 0; r < ranks; ++r) {
    for (uint32_t& id : reply[r]) id += static_cast<uint32_t>(offset);
    ids[r].resize(reply[r].size() * 4);
    std::memcpy(ids[r].data(), reply[r].data(), ids[r].size());
  }
  const RankBytes back = all_to_all(m, std::move(ids));
  nb.id.resize(keys.size());
  std::vector<size_t> next(ranks, 0);
  for (size_t c = 0; c < keys.size(); ++c) {
    const auto r = static_cast<size_t>(owner_of(cut, keys[c]));
    if (back[r].size() < 4 * (next[r] + 1)) throw Error("internal error: a rank numbered fewer DAG classes than it got");
    std::memcpy(&nb.id[c], back[r].data() + 4 * next[r]++, 4);
  }

  MessageWriter share;
  for (const Item* it : distinct) share.bytes.insert(share.bytes.end(), it->bytes, it->bytes + it->size);
  m.bytes_exchanged += m.ranks.rank == 0 ? 0 : share.bytes.size();
  const RankBytes shares = m.ranks.gather(std::move(share.bytes));
  m.bytes_exchanged += bytes_of_others(shares, 0);
  level = DagLevel();
  for (const std::vector<uint8_t>& b : shares)
    for (const uint8_t* at = b.data(); at < b.data() + b.size(); at += class_bytes(at, b.data() + b.size(), symmetric))
      append_class(level, at, symmetric);
  return nb;
}

// Each node's class id, from this rank's numbering to every rank's (kernel gather_slots: out[i] = id[node[i]]).
void renumber(Device& dev, Reduced& r, uint32_t n, const std::vector<uint32_t>& global) {
  if (!n) return;
  Buffer table = dev.alloc(uint64_t{std::max<size_t>(global.size(), 1)} * 4, "class ids over ranks");
  if (!global.empty()) dev.upload(table, global.data(), global.size() * 4);
  Buffer id = dev.alloc(uint64_t{n} * 4, "node ids over ranks"), none;
  dev.dispatch(dev.kernel(KernelId::gather_slots), dev.groups_for(n, kLocal), kLocal,
               {&r.id, &none, &table, &none, &id, &none}, MvDagParams{n, 0, 0, 0, 0, 0});
  dev.barrier();
  r.id = std::move(id);
}

std::vector<uint32_t> fetch_u32(Device& dev, const Buffer& b, uint32_t n) {
  std::vector<uint32_t> v(n);
  if (n) dev.download(b, v.data(), uint64_t{n} * 4);
  return v;
}

}  // namespace

Reduced cube_roots_at_lead(Device& dev, const Reduced& top, uint32_t top_n, bool symmetric,
                           std::vector<uint64_t>& keys, std::vector<uint32_t>& nodes, RankMerge& m) {
  const std::vector<uint32_t> ids = fetch_u32(dev, top.id, top_n);
  const std::vector<uint32_t> rows = symmetric ? fetch_u32(dev, top.row, top_n) : std::vector<uint32_t>();
  std::vector<uint32_t> id, row;
  for (uint32_t node : nodes) {
    id.push_back(ids.at(node));
    if (symmetric) row.push_back(rows.at(node));
  }
  MessageWriter w;
  w.put_all(keys);
  w.put_all(id);
  w.put_all(row);
  m.bytes_exchanged += m.ranks.rank == 0 ? 0 : w.bytes.size();
  const RankBytes all = m.ranks.gather(std::move(w.bytes));
  m.bytes_exchanged += bytes_of_others(all, 0);
  Reduced r;
  if (m.ranks.rank != 0) return r;
  struct Root {
    uint64_t key;
    uint32_t id, row;
  };
  std::vector<Root> roots;
  for (const std::vector<uint8_t>& b : all) {
    MessageReader in(b);
    in.get_all(keys);
    in.get_all(id);
    in.get_all(row);
    if (id.size() != keys.size() || (symmetric && row.size() != keys.size()))
      throw Error("internal error: a rank's cube roots do not match their classes");
    for (size_t i = 0; i < keys.size(); ++i) roots.push_back({keys[i], id[i], symmetric ? row[i] : 0});
  }
  std::sort(roots.begin(), roots.end(), [](const Root& a, const Root& b) { return a.key < b.key; });
  keys.clear();
  nodes.clear();
  id.clear();
  row.clear();
  for (const Root& root : roots) {
    nodes.push_back(static_cast<uint32_t>(keys.size()));
    keys.push_back(root.key);
    id.push_back(root.id);
    row.push_back(root.row);
  }
  const auto n = static_cast<uint32_t>(roots.size());
  r.distinct = top.distinct;
  r.id = dev.alloc(uint64_t{n} * 4, "cube root classes");
  dev.upload(r.id, id.data(), uint64_t{n} * 4);
  if (symmetric) {
    r.row = dev.alloc(uint64_t{n} * 4, "cube root orientations");
    dev.upload(r.row, row.data(), uint64_t{n} * 4);
  }
  return r;
}

Reduced reduce_level_over_ranks(Device& dev, const SvoLevel& lv, const Reduced& slots, bool leaf,
                                const Reduction& red, RankMerge& m, DagLevel& level) {
  if (leaf) return leaf_classes(dev, lv, red, m, level);
  for (uint32_t seed = 1;; ++seed) {
    // A seed holds for the level when it holds on every rank (no two different nodes of one rank share a
    // hash) and across them (checked by the owners): the first such seed is the one process's.
    Reduced r;
    ClassKeys keys;
    for (;;) {
      keys.seed = seed;
      if (lv.n) r = reduce_level(dev, lv, slots, false, red, &keys);
      MessageWriter w;
      w.put(keys.seed);
      uint32_t high = keys.seed;
      bool same = true;
      for (const std::vector<uint8_t>& b : all_gather(m, std::move(w.bytes))) {
        const auto s = MessageReader(b).get<uint32_t>();
        same = same && s == keys.seed;
        high = std::max(high, s);
      }
      if (same) break;
      seed = high;
    }
    seed = keys.seed;
    DagLevel mine;
    if (lv.n) mine = assemble(dev, lv, r, slots, false, red);
    Numbered nb = number_classes(keys.keys, mine, red.symmetric, m, level);
    if (!nb.collided) {
      renumber(dev, r, lv.n, nb.id);
      r.distinct = nb.distinct;
      return r;
    }
    if (m.ranks.rank == 0) report_test_collision("across ranks", seed);
    if (seed >= kMaxSeed) throw Error("DAG reduction over ranks: 16 hash seeds collided; this should not happen");
  }
}

}  // namespace mv::detail

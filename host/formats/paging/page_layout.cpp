#include "paging/page_layout.h"

#include <algorithm>
#include <deque>
#include <random>

#include "encode/node_starts.h"
#include "megavox/error.h"

namespace mv {
namespace {

// The nodes of a validated 32-bit word stream, in stream order: start word, size, level, children (node ids).
struct Nodes {
  std::vector<uint32_t> at;
  std::vector<uint8_t> size, level;
  std::vector<uint32_t> first;     // children of node k: child[first[k] .. first[k + 1])
  std::vector<uint32_t> child;
};

Nodes parse(const EncodedDag& enc) {
  Nodes n;
  for (uint32_t l = enc.levels; l >= 1; --l) {
    const uint64_t end = l == 1 ? enc.words.size() : enc.level_offset[l - 1];
    for (uint64_t w = enc.level_offset[l]; w < end;) {
      const uint32_t size = l == 1 ? 1 : 1 + __builtin_popcount(enc.words[w] & 0xffu);
      n.at.push_back(static_cast<uint32_t>(w));
      n.size.push_back(static_cast<uint8_t>(size));
      n.level.push_back(static_cast<uint8_t>(l));
      w += size;
    }
  }
  NodeStarts starts(enc.words.size());  // node k starts at n.at[k], ascending: its index is k
  for (uint32_t w : n.at) starts.set(w);
  starts.count();
  n.first.push_back(0);
  for (size_t k = 0; k < n.at.size(); ++k) {
    for (uint32_t q = 1; q < n.size[k]; ++q) n.child.push_back(starts.index(enc.words[n.at[k] + q]));
    n.first.push_back(static_cast<uint32_t>(n.child.size()));
  }
  return n;
}

// Does a node of `size` words fit in the page after `fill` words?
bool fits(uint64_t fill, uint32_t size, uint32_t page_words) { return fill % page_words + size <= page_words; }

std::vector<uint32_t> subtree_order(const Nodes& n, uint32_t page_words) {
  std::vector<uint32_t> order;
  order.reserve(n.at.size());
  std::vector<bool> placed(n.at.size(), false);
  std::deque<uint32_t> roots{0};
  uint64_t fill = 0;  // words placed so far, as the packing will lay them out
  while (!roots.empty()) {
    const uint32_t r = roots.front();
    roots.pop_front();
    if (placed[r]) continue;
    std::deque<uint32_t> walk{r};
    while (!walk.empty()) {
      const uint32_t k = walk.front();
      if (placed[k]) {
        walk.pop_front();
        continue;
      }
      if (!fits(fill, n.size[k], page_words)) {  // page full: the frontier roots the next pages
        fill += page_words - fill % page_words;
        roots.insert(roots.end(), walk.begin(), walk.end());
        break;
      }
      walk.pop_front();
      placed[k] = true;
      order.push_back(k);
      fill += n.size[k];
      for (uint32_t j = n.first[k]; j < n.first[k + 1]; ++j)
        if (!placed[n.child[j]]) walk.push_back(n.child[j]);
      if (fill % page_words == 0) {  // exactly full
        roots.insert(roots.end(), walk.begin(), walk.end());
        break;
      }
    }
  }
  return order;
}

}  // namespace

std::string node_order_name(NodeOrder o) { return o == NodeOrder::level ? "level" : "subtree"; }

PageLayout page_layout(const EncodedDag& enc, NodeOrder order, uint32_t page_words) {
  if (enc.encoding == Encoding::ssvdag)
    throw Error("page layout: node orders are for svo, svdag and ussvdag; the ssvdag is paged in level order only "
                "(host/formats/paging/paged_ssvdag.h)");
  if (page_words < kMaxNodeWords)
    throw Error("page layout: a page of " + std::to_string(page_words) + " words cannot hold a node of " +
                std::to_string(kMaxNodeWords));
  validate_encoded(enc);
  PageLayout lay;
  lay.order = order;
  lay.page_words = page_words;
  if (enc.words.empty()) return lay;
  const Nodes n = parse(enc);
  std::vector<uint32_t> seq;
  if (order == NodeOrder::subtree) {
    seq = subtree_order(n, page_words);
  } else {
    seq.resize(n.at.size());
    for (uint32_t k = 0; k < seq.size(); ++k) seq[k] = k;
  }
  lay.old_at = n.at;
  lay.at.assign(n.at.size(), 0);
  uint64_t pos = 0;
  for (uint32_t k : seq) {
    if (!fits(pos, n.size[k], page_words)) pos += page_words - pos % page_words;
    lay.at[k] = pos;
    pos += n.size[k];
  }
  lay.words = pos;
  return lay;
}

PageLayoutStats measure_page_layout(const EncodedDag& enc, const PageLayout& lay, uint32_t paths, uint64_t seed) {
  PageLayoutStats st;
  if (enc.words.empty()) return st;
  const Nodes n = parse(enc);
  if (lay.at.size() != n.at.size()) throw Error("page layout: made for another DAG");
  auto page = [&](uint32_t k) { return lay.at[k] / lay.page_words; };
  st.nodes = n.at.size();
  st.words = enc.words.size();
  st.paged_words = lay.words;
  st.pages = lay.pages();
  st.size_ratio = double(st.paged_words) / double(st.words);
  st.pointers = n.child.size();
  for (uint32_t k = 0; k < n.at.size(); ++k)
    for (uint32_t j = n.first[k]; j < n.first[k + 1]; ++j) st.crossing += page(k) != page(n.child[j]) ? 1 : 0;
  st.levels = enc.levels;
  std::mt19937_64 rng(seed);
  uint64_t total = 0;
  std::vector<uint64_t> seen;
  for (uint32_t p = 0; p < paths; ++p) {
    seen.clear();
    for (uint32_t k = 0;;) {
      if (std::find(seen.begin(), seen.end(), page(k)) == seen.end()) seen.push_back(page(k));
      const uint32_t kids = n.first[k + 1] - n.first[k];
      if (kids == 0) break;
      k = n.child[n.first[k] + rng() % kids];
    }
    total += seen.size();
    st.max_pages_per_path = std::max<uint32_t>(st.max_pages_per_path, static_cast<uint32_t>(seen.size()));
  }
  st.pages_per_path = paths ? double(total) / paths : 0;
  return st;
}

}  // namespace mv

// megavox — what one update of the device page cache did (plain data): reported per pass by paged ray
// queries and renders (megavox/trace.h, megavox/render.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mv {

// What one update after a pass did. requested counts the distinct missing pages asked for in the pass; of those, the first
// `loaded + failed` (in page order) got a victim slot, and `dropped` did not (over the unused slots or
// max_loads: asked again by the next pass that still needs them).
struct CacheUpdateStats {
  uint32_t stamp = 0;          // the pass this update followed
  uint32_t used_slots = 0;     // slots whose usage stamp is this pass (read in it, or loaded for it)
  uint32_t requested = 0;
  uint32_t loaded = 0;         // produced and entered into the page table
  uint32_t failed = 0;         // the producer could not make them: still missing, their slots free
  uint32_t evicted = 0;        // resident pages whose slots were reused
  uint32_t dropped = 0;
  uint32_t read_ahead = 0;     // of the produced pages, those read while the pass still traced (Tracer::read_ahead)
  bool over_capacity = false;  // more requests than slots unused in the pass (the frame's working set does
                               // not fit: the used pages stay, the rest waits)
  uint64_t bytes_uploaded = 0;
  double manage_seconds = 0;   // the kernels and the host's waits on them
  double produce_seconds = 0;  // the producer, the upload of its batch and its placement into the slots
  double read_ahead_seconds = 0;  // reading the read_ahead pages, on its own thread while the pass traced
  std::string first_error;     // the first producer failure's message, if it threw one
};

// A frame's or a batch's updates summed. hit_rate: of the pages its passes needed (used slots plus requests),
// the share already resident.
struct CacheTotals {
  uint64_t requested = 0, loaded = 0, evicted = 0, failed = 0, used = 0, bytes_uploaded = 0, read_ahead = 0;
  double manage_seconds = 0, produce_seconds = 0, read_ahead_seconds = 0;
  double hit_rate() const { return used + requested ? double(used) / double(used + requested) : 1.0; }
};

inline CacheTotals cache_totals(const std::vector<CacheUpdateStats>& passes) {
  CacheTotals t;
  for (const CacheUpdateStats& st : passes) {
    t.requested += st.requested, t.loaded += st.loaded, t.evicted += st.evicted, t.failed += st.failed;
    t.used += st.used_slots, t.bytes_uploaded += st.bytes_uploaded, t.read_ahead += st.read_ahead;
    t.manage_seconds += st.manage_seconds, t.produce_seconds += st.produce_seconds;
    t.read_ahead_seconds += st.read_ahead_seconds;
  }
  return t;
}

}  // namespace mv

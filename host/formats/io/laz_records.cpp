// The LAZ record reader (laz_records.h).
#include "laz_records.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <exception>
#include <thread>
#include <unordered_map>

#include "file_ops.h"
#include "laz/copc_hierarchy.h"
#include "io/header_numbers.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

using detail::num;

uint64_t point_data_end(const detail::LasHeader& h, uint64_t file_size) {
  return h.evlr_count != 0 && h.evlr_start > h.point_offset ? h.evlr_start : file_size;
}

}  // namespace

LazRecords::LazRecords(std::FILE* file, const std::string& path, uint64_t file_size, const detail::LasHeader& h,
                       unsigned threads, uint64_t ram_bytes, const std::optional<std::array<double, 6>>& bounds)
    : file_(file), path_(path), ram_bytes_(ram_bytes) {
  try {
    schema_ = laz::parse_schema(h.laszip.data(), h.laszip.size(), h.point_format, h.record_length);
  } catch (const laz::LazError& e) {
    throw Error(path + ": " + e.what());
  }
  chunks_ = laz::read_chunks(file, path, file_size, schema_, h.point_offset, point_data_end(h, file_size), h.points);
  chunks_in_file_ = chunks_.size();
  const std::optional<laz::CopcInfo> copc = laz::parse_copc_info(h.copc.data(), h.copc.size());
  copc_ = copc.has_value();
  if (copc && bounds) keep_chunks_meeting(*copc, *bounds, file_size);
  for (const laz::Chunk& c : chunks_) points_ += c.points;
  threads_ = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

// COPC: the chunks whose node cube meets `box`, and any chunk the hierarchy does not name (read, to be safe).
void LazRecords::keep_chunks_meeting(const laz::CopcInfo& info, const std::array<double, 6>& box, uint64_t file_size) {
  std::unordered_map<uint64_t, const laz::CopcNode*> by_offset;
  const std::vector<laz::CopcNode> nodes = laz::read_copc_nodes(file_, path_, file_size, info);
  for (const laz::CopcNode& n : nodes) by_offset[n.offset] = &n;
  std::vector<laz::Chunk> kept;
  for (const laz::Chunk& c : chunks_) {
    const auto it = by_offset.find(c.offset);
    bool meets = true;
    if (it != by_offset.end()) {
      double lo[3], hi[3];
      it->second->cube(info, lo, hi);
      for (int a = 0; a < 3; ++a) meets = meets && lo[a] <= box[3 + a] && box[a] <= hi[a];
    }
    if (meets) kept.push_back(c);
  }
  chunks_ = std::move(kept);
}

size_t LazRecords::read(uint8_t* out, size_t count) {
  const size_t length = schema_.record_length;
  size_t done = 0;
  while (done < count) {
    if (ready_at_ == ready_.size()) {
      if (next_chunk_ == chunks_.size() && !big_) break;
      // Whole chunks that fit what the caller still wants go straight into its buffer: no copy, and no second
      // buffer of fresh pages to fault in.
      if (!big_) {
        const size_t end = batch_end(count - done);
        if (end != next_chunk_) {
          done += decode_chunks(end, out + done * length);
          continue;
        }
      }
      decode_batch();
    }
    const size_t take = std::min(count - done, (ready_.size() - ready_at_) / length);
    std::memcpy(out + done * length, ready_.data() + ready_at_, take * length);
    ready_at_ += take * length;
    done += take;
  }
  return done;
}

uint64_t LazRecords::skip_chunks(uint64_t count) {
  if (ready_at_ != ready_.size() || big_) return 0;
  uint64_t passed = 0;
  while (next_chunk_ < chunks_.size() && passed + chunks_[next_chunk_].points <= count)
    passed += chunks_[next_chunk_++].points;
  return passed;
}

std::vector<uint8_t> LazRecords::chunk_bytes(size_t c) {
  return read_at(file_, chunks_[c].offset, chunks_[c].bytes, path_);  // read_chunks placed it inside the file
}

[[noreturn]] void LazRecords::chunk_failed(size_t c, const laz::LazError& e) const {
  const laz::Chunk& k = chunks_[c];
  throw Error(path_ + ": corrupt LAZ in chunk " + num(c) + " (points " + num(k.first_point) + " to " +
              num(k.first_point + k.points - 1) + ", bytes from " + num(k.offset) + "): " + e.what());
}

// The next records into ready_: a run of a chunk too large for the buffer (decoded on this thread, a run at a
// time), else the next chunks that fit it, read in order on this thread and decoded on up to threads_ threads.
void LazRecords::decode_batch() {
  const size_t length = schema_.record_length;
  const uint64_t buffer = std::min(ram_bytes_, kMaxBatchBytes);
  if (big_ || chunks_[next_chunk_].points * length > buffer) {
    try {
      if (!big_) {
        big_bytes_ = chunk_bytes(next_chunk_);
        big_ = laz::open_chunk(schema_, big_bytes_.data(), big_bytes_.size(), chunks_[next_chunk_].points);
        big_left_ = chunks_[next_chunk_].points;
      }
      const uint64_t n = std::min(big_left_, std::max<uint64_t>(1, buffer / length));
      ready_.resize(n * length);
      ready_at_ = 0;
      big_->next(ready_.data(), n);
      big_left_ -= n;
    } catch (const laz::LazError& e) {
      chunk_failed(next_chunk_, e);
    }
    if (big_left_ == 0) {
      big_.reset();
      big_bytes_ = {};
      ++next_chunk_;
    }
    return;
  }

  const size_t end = batch_end(buffer / length);
  uint64_t records = 0;
  for (size_t c = next_chunk_; c < end; ++c) records += chunks_[c].points;
  ready_.resize(records * length);
  ready_at_ = 0;
  decode_chunks(end, ready_.data());
}

// The end of the next batch: the chunks from next_chunk_ on, at most 4 a thread, of at most `room` records in all.
size_t LazRecords::batch_end(uint64_t room) const {
  size_t end = next_chunk_;
  uint64_t records = 0;
  while (end < chunks_.size() && end - next_chunk_ < 4 * threads_ && records + chunks_[end].points <= room)
    records += chunks_[end++].points;
  return end;
}

// Chunks [next_chunk_, end) read in order on this thread and decoded into `dest` on up to threads_ threads;
// returns their records.
uint64_t LazRecords::decode_chunks(size_t end, uint8_t* dest) {
  const size_t length = schema_.record_length;
  std::vector<std::vector<uint8_t>> coded;
  for (size_t c = next_chunk_; c < end; ++c) coded.push_back(chunk_bytes(c));
  std::vector<uint64_t> at(end - next_chunk_ + 1, 0);
  for (size_t c = next_chunk_; c < end; ++c) at[c - next_chunk_ + 1] = at[c - next_chunk_] + chunks_[c].points;
  std::vector<std::exception_ptr> failed(end - next_chunk_);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next.fetch_add(1)) < coded.size();) {
      try {
        laz::decode_chunk(schema_, coded[i].data(), coded[i].size(), chunks_[next_chunk_ + i].points,
                          dest + at[i] * length);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    }
  };
  const size_t workers = std::min<size_t>(threads_, coded.size());
  std::vector<std::thread> pool;
  for (size_t t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();

  for (size_t i = 0; i < failed.size(); ++i) {
    if (!failed[i]) continue;
    try {
      std::rethrow_exception(failed[i]);
    } catch (const laz::LazError& e) {
      chunk_failed(next_chunk_ + i, e);
    }
  }
  next_chunk_ = end;
  return at.back();
}

}  // namespace mv::io

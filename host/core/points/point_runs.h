// The out-of-core Morton sort of a point cloud: runs that fit the host budget are sorted on the device and
// written to scratch files as fixed-size records (code, then every column); a k-way merge then streams them
// back in order, so the builder consumes a sorted prefix while the merge goes on. Equal codes keep their input
// order (runs are in input order, each sorted stably), so the result equals the in-core sort.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "io/temp_file.h"
#include "megavox/device.h"
#include "megavox/points.h"
#include "point_kernels.h"

namespace mv::points {

// Bytes of one point's record in a run file: its 8-byte code, then its columns.
struct RecordLayout {
  uint32_t bytes = 20;
  uint32_t attributes = 0;
  uint32_t extra_bytes = 0;
};
RecordLayout record_layout(const PointCloudInfo& info);
void pack(const RecordLayout& r, const PointColumns& c, uint64_t i, uint64_t code, uint8_t* out);
// Appends the point of `rec` to `out`.
void unpack(const RecordLayout& r, const uint8_t* rec, PointColumns& out);
// Writes the point of `rec` as point i of `out`, whose columns hold at least i + 1 points (columns_for).
void unpack_at(const RecordLayout& r, const uint8_t* rec, PointColumns& out, uint64_t i);
// Columns of n points (zeros) for the columns `r` carries.
PointColumns columns_for(const RecordLayout& r, uint64_t n);
inline uint64_t record_code(const uint8_t* rec) {
  uint64_t code;
  __builtin_memcpy(&code, rec, 8);
  return code;
}

class RunSorter {
 public:
  RunSorter(Device& dev, const PointCloudInfo& info, const PointCube& cube);
  ~RunSorter();

  // Sorts one run on the device and writes it out.
  void add_run(const PointColumns& run);
  uint64_t runs() const { return runs_.size(); }
  uint64_t points() const { return points_; }

  // Streams every record in order to `sink` (at most batch_records at a time, in buffers reused between calls).
  void merge(size_t batch_records, const std::function<void(const uint8_t* records, size_t count)>& sink);

 private:
  struct Run {
    std::unique_ptr<io::TempFile> file;
    uint64_t records = 0;
  };
  Device& dev_;
  RecordLayout layout_;
  PointCube cube_;
  std::vector<Run> runs_;
  uint64_t points_ = 0;
};

}  // namespace mv::points

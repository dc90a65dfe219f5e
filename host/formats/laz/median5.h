// The running median of the last five values that LAZ predicts x and y differences with: a sorted window
// that, value by value, alternately drops its lowest and its highest entry. LASzip's exact rule, so it is
// part of the format (a true median predicts other values and decodes another stream).
#pragma once
#include <array>
#include <cstdint>

namespace mv::laz {

class Median5 {
 public:
  int32_t get() const { return v_[2]; }
  void add(int32_t x) {
    if (high_) {
      if (x < v_[2]) {
        v_[4] = v_[3], v_[3] = v_[2];
        if (x < v_[0]) v_[2] = v_[1], v_[1] = v_[0], v_[0] = x;
        else if (x < v_[1]) v_[2] = v_[1], v_[1] = x;
        else v_[2] = x;
      } else {
        if (x < v_[3]) v_[4] = v_[3], v_[3] = x;
        else v_[4] = x;
        high_ = false;
      }
    } else {
      if (v_[2] < x) {
        v_[0] = v_[1], v_[1] = v_[2];
        if (v_[4] < x) v_[2] = v_[3], v_[3] = v_[4], v_[4] = x;
        else if (v_[3] < x) v_[2] = v_[3], v_[3] = x;
        else v_[2] = x;
      } else {
        if (v_[1] < x) v_[0] = v_[1], v_[1] = x;
        else v_[0] = x;
        high_ = true;
      }
    }
  }

 private:
  std::array<int32_t, 5> v_{};
  bool high_ = true;
};

}  // namespace mv::laz

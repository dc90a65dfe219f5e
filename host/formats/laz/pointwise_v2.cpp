// Version 2 of the pointwise item coders (LASzip 2.0 on, the common LAZ of point formats 0-3):
// - POINT10: a 6-bit mask says which of the non-coordinate fields changed; x and y are coded as differences
//   predicted by the median of the last five differences of the same return kind, z against the last z of the
//   same return level; the corrector buckets of x feed y's and z's contexts.
// - GPSTIME11: up to four interleaved time sequences, each coded as a multiple of its last difference.
// - RGB12: the low and high bytes of each channel, green and blue predicted from red's change.
// - BYTE10: each extra byte as the difference to its last value.
#include <array>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "median5.h"
#include "pointwise_items.h"

namespace mv::laz {

namespace {

uint16_t get_u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t get_u32(const uint8_t* p) { return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<uint32_t>(p[3]) << 24); }
void put_u16(uint8_t* p, uint16_t v) { p[0] = v & 0xFF, p[1] = v >> 8; }
void put_u32(uint8_t* p, uint32_t v) { p[0] = v & 0xFF, p[1] = (v >> 8) & 0xFF, p[2] = (v >> 16) & 0xFF, p[3] = v >> 24; }

// Context of a return (r of n): one of 16 kinds, with "first of many", "last of many" and "only" apart.
// The table also gives distinct contexts to files that number returns from 0 or swap r and n.
constexpr uint8_t kReturnKind[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8}, {14, 0, 1, 3, 6, 10, 10, 9},    {13, 1, 2, 4, 7, 11, 11, 10},
    {12, 3, 4, 5, 8, 12, 12, 11},   {11, 6, 7, 8, 9, 13, 13, 12},   {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};
// The return's level: how far r is from n (0 for the last return).
constexpr uint8_t kReturnLevel[8][8] = {{0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5},
                                        {3, 2, 1, 0, 1, 2, 3, 4}, {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2},
                                        {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0}};

// 256 symbol models created on first use (most files touch a handful of them).
class LazyModels {
 public:
  SymbolModel& operator[](uint8_t i) {
    if (!m_[i]) m_[i] = std::make_unique<SymbolModel>(256);
    return *m_[i];
  }

 private:
  std::array<std::unique_ptr<SymbolModel>, 256> m_;
};

class Point10V2 final : public PointwiseItem {
 public:
  void first(const uint8_t* raw) override {
    std::memcpy(last_, raw, 20);
    put_u16(last_ + 12, 0);  // intensity is predicted from last_intensity_, never from the first point
  }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    uint8_t* p = last_;
    const uint32_t changed = dec.decode_symbol(changed_);
    if (changed & 32) p[14] = static_cast<uint8_t>(dec.decode_symbol(bit_byte_[p[14]]));
    const unsigned r = p[14] & 7, n = (p[14] >> 3) & 7;
    const unsigned kind = kReturnKind[n][r], level = kReturnLevel[n][r];
    if (changed) {
      if (changed & 16) {
        last_intensity_[kind] = static_cast<uint16_t>(intensity_.decode(dec, last_intensity_[kind], kind < 3 ? kind : 3));
      }
      if (changed & 8) p[15] = static_cast<uint8_t>(dec.decode_symbol(classification_[p[15]]));
      if (changed & 4) p[16] = static_cast<uint8_t>(p[16] + dec.decode_symbol(scan_angle_[(p[14] >> 6) & 1]));
      if (changed & 2) p[17] = static_cast<uint8_t>(dec.decode_symbol(user_data_[p[17]]));
      if (changed & 1) put_u16(p + 18, static_cast<uint16_t>(source_.decode(dec, get_u16(p + 18))));
    }
    put_u16(p + 12, last_intensity_[kind]);

    const int32_t dx = dx_.decode(dec, median_x_[kind].get(), n == 1);
    put_u32(p, get_u32(p) + static_cast<uint32_t>(dx));
    median_x_[kind].add(dx);
    uint32_t k = dx_.k();
    const int32_t dy = dy_.decode(dec, median_y_[kind].get(), (n == 1) + (k < 20 ? k & ~1u : 20));
    put_u32(p + 4, get_u32(p + 4) + static_cast<uint32_t>(dy));
    median_y_[kind].add(dy);
    k = (dx_.k() + dy_.k()) / 2;
    last_z_[level] = z_.decode(dec, last_z_[level], (n == 1) + (k < 18 ? k & ~1u : 18));
    put_u32(p + 8, static_cast<uint32_t>(last_z_[level]));
    std::memcpy(out, p, 20);
  }

 private:
  uint8_t last_[20] = {};
  std::array<uint16_t, 16> last_intensity_{};
  std::array<int32_t, 8> last_z_{};
  std::array<Median5, 16> median_x_, median_y_;
  SymbolModel changed_{64};
  std::array<SymbolModel, 2> scan_angle_{SymbolModel(256), SymbolModel(256)};
  LazyModels bit_byte_, classification_, user_data_;
  IntegerDecoder intensity_{16, 4}, source_{16}, dx_{32, 2}, dy_{32, 22}, z_{32, 20};
};

class GpsTime11V2 final : public PointwiseItem {
 public:
  void first(const uint8_t* raw) override {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | raw[i];
    time_[0] = v;
  }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    // A switch to another sequence decodes the time again; at most three switches make sense, and a stream
    // that keeps switching is corrupt.
    for (int guard = 0;; ++guard) {
      if (guard > 4) throw LazError("GPS times switch sequences endlessly");
      if (step(dec)) break;
    }
    uint64_t v = time_[last_];
    for (int i = 0; i < 8; ++i, v >>= 8) out[i] = static_cast<uint8_t>(v);
  }

 private:
  static constexpr int32_t kMulti = 500, kMultiMinus = -10;
  static constexpr uint32_t kUnchanged = kMulti - kMultiMinus + 1, kCodeFull = kMulti - kMultiMinus + 2;
  static constexpr uint32_t kTotal = kMulti - kMultiMinus + 6;

  static int32_t times(int32_t a, int32_t b) {
    return static_cast<int32_t>(static_cast<uint32_t>(a) * static_cast<uint32_t>(b));
  }
  void add(int32_t d) { time_[last_] += static_cast<uint64_t>(static_cast<int64_t>(d)); }
  void full(ArithmeticDecoder& dec) {
    next_ = (next_ + 1) & 3;
    const uint32_t high = static_cast<uint32_t>(ic_.decode(dec, static_cast<int32_t>(time_[last_] >> 32), 8));
    time_[next_] = (static_cast<uint64_t>(high) << 32) | dec.read_int();
    last_ = next_;
    diff_[last_] = 0;
    extreme_[last_] = 0;
  }
  // After three extreme differences in a row the extreme becomes the sequence's difference.
  void extreme(int32_t d) {
    if (++extreme_[last_] > 3) diff_[last_] = d, extreme_[last_] = 0;
  }

  // Decodes one time; false when the stream switched to another sequence and the time follows.
  bool step(ArithmeticDecoder& dec) {
    if (diff_[last_] == 0) {
      const uint32_t multi = dec.decode_symbol(zero_diff_);
      if (multi == 1) {
        diff_[last_] = ic_.decode(dec, 0, 0);
        add(diff_[last_]);
        extreme_[last_] = 0;
      } else if (multi == 2) {
        full(dec);
      } else if (multi > 2) {
        last_ = (last_ + multi - 2) & 3;
        return false;
      }
      return true;
    }
    const uint32_t code = dec.decode_symbol(multi_);
    const int32_t diff = diff_[last_];
    if (code == 1) {
      add(ic_.decode(dec, diff, 1));
      extreme_[last_] = 0;
    } else if (code < kUnchanged) {
      int32_t d;
      if (code == 0) {
        d = ic_.decode(dec, 0, 7);
        extreme(d);
      } else if (code < static_cast<uint32_t>(kMulti)) {
        d = ic_.decode(dec, times(static_cast<int32_t>(code), diff), code < 10 ? 2 : 3);
      } else if (code == static_cast<uint32_t>(kMulti)) {
        d = ic_.decode(dec, times(kMulti, diff), 4);
        extreme(d);
      } else {
        const int32_t multi = kMulti - static_cast<int32_t>(code);
        if (multi > kMultiMinus) {
          d = ic_.decode(dec, times(multi, diff), 5);
        } else {
          d = ic_.decode(dec, times(kMultiMinus, diff), 6);
          extreme(d);
        }
      }
      add(d);
    } else if (code == kCodeFull) {
      full(dec);
    } else if (code > kCodeFull) {
      last_ = (last_ + code - kCodeFull) & 3;
      return false;
    }
    return true;
  }

  std::array<uint64_t, 4> time_{};
  std::array<int32_t, 4> diff_{}, extreme_{};
  uint32_t last_ = 0, next_ = 0;
  SymbolModel multi_{kTotal}, zero_diff_{6};
  IntegerDecoder ic_{32, 9};
};

uint8_t clamp_byte(int v) { return static_cast<uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v); }

class Rgb12V2 final : public PointwiseItem {
 public:
  void first(const uint8_t* raw) override {
    for (int c = 0; c < 3; ++c) last_[c] = get_u16(raw + 2 * c);
  }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    const uint32_t sym = dec.decode_symbol(used_);
    auto byte_of = [&](uint32_t bit, int model, int predicted) -> unsigned {
      return sym & bit ? static_cast<uint8_t>(dec.decode_symbol(diff_[model]) + predicted) : 0;
    };
    uint16_t r, g, b;
    r = sym & 1 ? byte_of(1, 0, last_[0] & 0xFF) : last_[0] & 0xFF;
    r |= (sym & 2 ? byte_of(2, 1, last_[0] >> 8) : last_[0] >> 8) << 8;
    if (sym & 64) {
      int d = (r & 0xFF) - (last_[0] & 0xFF);
      g = sym & 4 ? byte_of(4, 2, clamp_byte(d + (last_[1] & 0xFF))) : last_[1] & 0xFF;
      if (sym & 16) {
        d = (d + (g & 0xFF) - (last_[1] & 0xFF)) / 2;
        b = byte_of(16, 4, clamp_byte(d + (last_[2] & 0xFF)));
      } else {
        b = last_[2] & 0xFF;
      }
      d = (r >> 8) - (last_[0] >> 8);
      g |= (sym & 8 ? byte_of(8, 3, clamp_byte(d + (last_[1] >> 8))) : last_[1] >> 8) << 8;
      if (sym & 32) {
        d = (d + (g >> 8) - (last_[1] >> 8)) / 2;
        b |= byte_of(32, 5, clamp_byte(d + (last_[2] >> 8))) << 8;
      } else {
        b |= last_[2] & 0xFF00;
      }
    } else {
      g = b = r;
    }
    last_ = {r, g, b};
    for (int c = 0; c < 3; ++c) put_u16(out + 2 * c, last_[c]);
  }

 private:
  std::array<uint16_t, 3> last_{};
  SymbolModel used_{128};
  std::array<SymbolModel, 6> diff_{SymbolModel(256), SymbolModel(256), SymbolModel(256),
                                   SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

class Byte10V2 final : public PointwiseItem {
 public:
  explicit Byte10V2(size_t n) : last_(n) { models_.reserve(n); for (size_t i = 0; i < n; ++i) models_.emplace_back(256); }
  void first(const uint8_t* raw) override { std::memcpy(last_.data(), raw, last_.size()); }
  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    for (size_t i = 0; i < last_.size(); ++i)
      out[i] = last_[i] = static_cast<uint8_t>(last_[i] + dec.decode_symbol(models_[i]));
  }

 private:
  std::vector<uint8_t> last_;
  std::vector<SymbolModel> models_;
};

}  // namespace

std::unique_ptr<PointwiseItem> make_pointwise_v2(const Item& item) {
  auto sized = [&](uint16_t size, const char* name) {
    if (item.size != size)
      throw LazError(std::string("a ") + name + " item of " + std::to_string(item.size) + " bytes (it has " +
                     std::to_string(size) + ")");
  };
  switch (item.type) {
    case ItemType::point10: sized(20, "POINT10"); return std::make_unique<Point10V2>();
    case ItemType::gpstime11: sized(8, "GPSTIME11"); return std::make_unique<GpsTime11V2>();
    case ItemType::rgb12: sized(6, "RGB12"); return std::make_unique<Rgb12V2>();
    case ItemType::byte10:
      if (item.size == 0) throw LazError("a BYTE item of 0 bytes");
      return std::make_unique<Byte10V2>(item.size);
    default: throw LazError("item type " + std::to_string(static_cast<unsigned>(item.type)) +
                            " has no version 2 pointwise coder");
  }
}

}  // namespace mv::laz

// The version-1 pointwise item coders (LASzip 1.0-1.3, files from 2010-2011): POINT10, GPSTIME11, RGB12 and
// BYTE10, decoding side. Files this old are still served by archives, so a LAZ reader meets them.
//
// Version 1 is a different code from version 2, not a variant of it: x and y are predicted from the median of
// the last three differences through 32-bit correctors, z from the last z; the other POINT10 fields are coded
// behind one 6-bit "changed" mask with symbol models keyed by the field's previous value; GPS time uses a
// multiplier alphabet of 512 symbols over one 6-context corrector; RGB12 codes each of its six bytes against
// the previous byte when a 6-bit mask says it changed; BYTE10 codes every byte against the previous one, each
// byte in its own context. The model sizes, contexts and the rules for when a remembered difference is
// replaced are part of the stream: they follow LASzip's v1 decoder exactly.
//
// Records are little-endian byte strings; every field is read and written through explicit byte helpers.
// Arithmetic that LASzip leaves to two's-complement wrap-around is done in unsigned types.
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "arithmetic_decoder.h"
#include "laz_schema.h"
#include "pointwise_items.h"

namespace mv::laz {
namespace {

uint16_t v1_get16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }

uint32_t v1_get32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}

uint64_t v1_get64(const uint8_t* p) {
  return static_cast<uint64_t>(v1_get32(p)) | (static_cast<uint64_t>(v1_get32(p + 4)) << 32);
}

void v1_put16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}

void v1_put32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

void v1_put64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

// The median of three, with LASzip's comparison order (ties resolve the same way).
int32_t v1_median3(const std::array<int32_t, 3>& d) {
  if (d[0] < d[1]) {
    if (d[1] < d[2]) return d[1];
    if (d[0] < d[2]) return d[2];
    return d[0];
  }
  if (d[0] < d[2]) return d[0];
  if (d[1] < d[2]) return d[2];
  return d[1];
}

// ---- POINT10 v1 ----------------------------------------------------------------------------------------
// Record: x, y, z (int32), intensity (uint16), the return/flags byte, classification, scan angle rank,
// user data, point source ID (uint16): 20 bytes.

constexpr size_t kV1Point10Size = 20;

// A symbol model per previous value of a byte field, made the first time that value is seen.
class V1ByteModels {
 public:
  uint8_t decode(ArithmeticDecoder& dec, uint8_t previous) {
    std::unique_ptr<SymbolModel>& m = models_[previous];
    if (!m) m = std::make_unique<SymbolModel>(256);
    return static_cast<uint8_t>(dec.decode_symbol(*m));
  }

 private:
  std::array<std::unique_ptr<SymbolModel>, 256> models_;
};

class V1Point10 final : public PointwiseItem {
 public:
  V1Point10()
      : dx_(32, 1), dy_(32, 20), z_(32, 20), intensity_(16, 1), scan_angle_(8, 2), source_id_(16, 1), changed_(64) {}

  void first(const uint8_t* raw) override {
    std::memcpy(last_, raw, kV1Point10Size);
    last_dx_ = {0, 0, 0};
    last_dy_ = {0, 0, 0};
    slot_ = 0;
  }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    const int32_t median_x = v1_median3(last_dx_);
    const int32_t median_y = v1_median3(last_dy_);

    // x and y are the previous coordinates plus a difference predicted by the median of the last three; the
    // bucket of x's corrector selects y's context, and the mean of both buckets selects z's.
    const int32_t x_diff = dx_.decode(dec, median_x);
    v1_put32(last_, v1_get32(last_) + static_cast<uint32_t>(x_diff));
    uint32_t k_bits = dx_.k();
    const int32_t y_diff = dy_.decode(dec, median_y, k_bits < 19 ? k_bits : 19);
    v1_put32(last_ + 4, v1_get32(last_ + 4) + static_cast<uint32_t>(y_diff));
    k_bits = (k_bits + dy_.k()) / 2;
    const int32_t z = z_.decode(dec, static_cast<int32_t>(v1_get32(last_ + 8)), k_bits < 19 ? k_bits : 19);
    v1_put32(last_ + 8, static_cast<uint32_t>(z));

    // Bit 5 intensity, 4 the flags byte, 3 classification, 2 scan angle, 1 user data, 0 point source ID.
    const uint32_t changed = dec.decode_symbol(changed_);
    if (changed != 0) {
      if (changed & 32u) {
        const int32_t v = intensity_.decode(dec, v1_get16(last_ + 12));
        v1_put16(last_ + 12, static_cast<uint16_t>(v));
      }
      if (changed & 16u) last_[14] = flags_.decode(dec, last_[14]);
      if (changed & 8u) last_[15] = classification_.decode(dec, last_[15]);
      if (changed & 4u) last_[16] = static_cast<uint8_t>(scan_angle_.decode(dec, last_[16], k_bits < 3 ? 1 : 0));
      if (changed & 2u) last_[17] = user_data_.decode(dec, last_[17]);
      if (changed & 1u) {
        const int32_t v = source_id_.decode(dec, v1_get16(last_ + 18));
        v1_put16(last_ + 18, static_cast<uint16_t>(v));
      }
    }

    last_dx_[slot_] = x_diff;
    last_dy_[slot_] = y_diff;
    slot_ = slot_ == 2 ? 0 : slot_ + 1;
    std::memcpy(out, last_, kV1Point10Size);
  }

 private:
  IntegerDecoder dx_, dy_, z_, intensity_, scan_angle_, source_id_;
  SymbolModel changed_;
  V1ByteModels flags_, classification_, user_data_;
  uint8_t last_[kV1Point10Size] = {};
  std::array<int32_t, 3> last_dx_{}, last_dy_{};
  uint32_t slot_ = 0;
};

// ---- GPSTIME11 v1 --------------------------------------------------------------------------------------
// The time is handled as the 64-bit integer of its double's bits. While the last integer difference is 0, a
// 3-symbol model says: same time (0), a new 32-bit difference (1), or a raw 64-bit time (2). Otherwise a
// 512-symbol model gives a multiplier of the last difference: 1 codes a new difference, 0 a difference near a
// quarter of it, 2-506 a multiple of it; 509 (the maximum less 3) is the largest multiple; 510 a raw time;
// 511 the same time. A difference coded at 0 or 509 replaces the remembered one only on its fourth time in a
// row, so that one outlier does not ruin the prediction.

constexpr uint32_t kV1GpsMultiMax = 512;

class V1GpsTime11 final : public PointwiseItem {
 public:
  V1GpsTime11() : multi_(kV1GpsMultiMax), zero_diff_(3), diff_(32, 6) {}

  void first(const uint8_t* raw) override {
    last_time_ = v1_get64(raw);
    last_diff_ = 0;
    extreme_count_ = 0;
  }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    if (last_diff_ == 0) {
      const uint32_t multi = dec.decode_symbol(zero_diff_);
      if (multi == 1) {
        last_diff_ = diff_.decode(dec, 0, 0);
        add(last_diff_);
      } else if (multi == 2) {
        last_time_ = read_raw_time(dec);
      }
    } else {
      const uint32_t multi = dec.decode_symbol(multi_);
      if (multi < kV1GpsMultiMax - 2) {
        int32_t diff;
        if (multi == 1) {
          diff = diff_.decode(dec, last_diff_, 1);
          last_diff_ = diff;
          extreme_count_ = 0;
        } else if (multi == 0) {
          diff = diff_.decode(dec, last_diff_ / 4, 2);
          note_extreme(diff);
        } else {
          // The product wraps in 32 bits, as LASzip's int multiplication does.
          const int32_t prediction = static_cast<int32_t>(multi * static_cast<uint32_t>(last_diff_));
          diff = diff_.decode(dec, prediction, multi < 10 ? 3 : multi < 50 ? 4 : 5);
          if (multi == kV1GpsMultiMax - 3) note_extreme(diff);
        }
        add(diff);
      } else if (multi == kV1GpsMultiMax - 2) {
        last_time_ = read_raw_time(dec);
      }
    }
    v1_put64(out, last_time_);
  }

 private:
  static uint64_t read_raw_time(ArithmeticDecoder& dec) {
    const uint64_t low = dec.read_int();
    const uint64_t high = dec.read_int();
    return (high << 32) | low;
  }

  void add(int32_t diff) { last_time_ += static_cast<uint64_t>(static_cast<int64_t>(diff)); }

  void note_extreme(int32_t diff) {
    if (++extreme_count_ > 3) {
      last_diff_ = diff;
      extreme_count_ = 0;
    }
  }

  SymbolModel multi_, zero_diff_;
  IntegerDecoder diff_;
  uint64_t last_time_ = 0;
  int32_t last_diff_ = 0;
  uint32_t extreme_count_ = 0;
};

// ---- RGB12 v1 ------------------------------------------------------------------------------------------
// Red, green, blue as uint16 little-endian: six bytes. A 6-bit mask (bit i for byte i) says which bytes
// changed; each changed byte is coded against its previous value in its own context of one 8-bit corrector.

constexpr size_t kV1Rgb12Size = 6;

class V1Rgb12 final : public PointwiseItem {
 public:
  V1Rgb12() : used_(64), byte_(8, 6) {}

  void first(const uint8_t* raw) override { std::memcpy(last_, raw, kV1Rgb12Size); }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    const uint32_t used = dec.decode_symbol(used_);
    for (uint32_t i = 0; i < kV1Rgb12Size; ++i)
      if (used & (1u << i)) last_[i] = static_cast<uint8_t>(byte_.decode(dec, last_[i], i));
    std::memcpy(out, last_, kV1Rgb12Size);
  }

 private:
  SymbolModel used_;
  IntegerDecoder byte_;
  uint8_t last_[kV1Rgb12Size] = {};
};

// ---- BYTE10 v1 -----------------------------------------------------------------------------------------
// Extra bytes: byte i is coded against its previous value in context i of one 8-bit corrector, every point.

class V1Byte10 final : public PointwiseItem {
 public:
  explicit V1Byte10(uint32_t size) : byte_(8, size), last_(size, 0) {}

  void first(const uint8_t* raw) override { std::memcpy(last_.data(), raw, last_.size()); }

  void next(ArithmeticDecoder& dec, uint8_t* out) override {
    for (uint32_t i = 0; i < last_.size(); ++i) last_[i] = static_cast<uint8_t>(byte_.decode(dec, last_[i], i));
    std::memcpy(out, last_.data(), last_.size());
  }

 private:
  IntegerDecoder byte_;
  std::vector<uint8_t> last_;
};

[[noreturn]] void v1_refuse(const Item& item, const std::string& why) {
  throw LazError("LAZ item type " + std::to_string(static_cast<unsigned>(item.type)) + " version " +
                 std::to_string(item.version) + " of " + std::to_string(item.size) + " bytes: " + why);
}

void v1_require_size(const Item& item, uint16_t size) {
  if (item.size != size) v1_refuse(item, "a version-1 item of this type is " + std::to_string(size) + " bytes");
}

}  // namespace

std::unique_ptr<PointwiseItem> make_pointwise_v1(const Item& item) {
  if (item.version != 1) v1_refuse(item, "not a version-1 item");
  switch (item.type) {
    case ItemType::point10:
      v1_require_size(item, kV1Point10Size);
      return std::make_unique<V1Point10>();
    case ItemType::gpstime11:
      v1_require_size(item, 8);
      return std::make_unique<V1GpsTime11>();
    case ItemType::rgb12:
      v1_require_size(item, kV1Rgb12Size);
      return std::make_unique<V1Rgb12>();
    case ItemType::byte10:
      if (item.size < 1) v1_refuse(item, "an extra-bytes item holds at least one byte");
      return std::make_unique<V1Byte10>(item.size);
    default:
      v1_refuse(item, "no version-1 pointwise coder for this type");
  }
}

}  // namespace mv::laz

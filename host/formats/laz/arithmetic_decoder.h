// The entropy decoder every LAZ item is coded with: Amir Said's fast arithmetic coder as LASzip fixes it
// (32-bit interval, periodic model updates, table-driven symbol search), its adaptive bit and symbol models,
// and LASzip's integer corrector that codes a value as a prediction plus a bucketed correction.
//
// The constants, the update schedule of both models and the bucket layout of the corrector are part of the
// LAZ format: a decoder that differs in any of them decodes a different stream. They follow the LAZ
// specification and LASzip's documented coder; the reference decoder this is checked against is laz-perf.
//
// Untrusted bytes: every read is bounded by the stream's end. A corrupt stream cannot read out of bounds or
// loop: reads past the end return zeros and are counted (overrun()), and an interval state no encoder can
// produce throws LazError.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mv::laz {

// A fault in the compressed data; the reader adds the file name and where.
struct LazError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline constexpr uint32_t kMinLength = 0x01000000u;  // renormalise below this interval length
inline constexpr uint32_t kMaxLength = 0xFFFFFFFFu;
inline constexpr uint32_t kBitLengthShift = 13;  // bit-model probabilities are 13-bit
inline constexpr uint32_t kBitMaxCount = 1u << 13;
inline constexpr uint32_t kSymbolLengthShift = 15;  // symbol-model distributions are 15-bit
inline constexpr uint32_t kSymbolMaxCount = 1u << 15;

// An adaptive binary model: the probability of a 0, re-estimated every update_cycle bits.
struct BitModel {
  uint32_t update_cycle = 4, until_update = 4;
  uint32_t zero_prob = 1u << (kBitLengthShift - 1), zero_count = 1, count = 2;

  void update() {
    if ((count += update_cycle) > kBitMaxCount) {
      count = (count + 1) >> 1;
      zero_count = (zero_count + 1) >> 1;
      if (zero_count == count) ++count;
    }
    zero_prob = (zero_count * (0x80000000u / count)) >> (31 - kBitLengthShift);
    update_cycle = (5 * update_cycle) >> 2;
    if (update_cycle > 64) update_cycle = 64;
    until_update = update_cycle;
  }
};

// An adaptive model over `symbols` symbols (2 to 2048): counts turned into a cumulative distribution every
// update cycle, with a lookup table that narrows the search for alphabets above 16 symbols. The table is the
// decoder's own (the stream does not depend on it): at least two entries a symbol, where LASzip has one per four,
// so a lookup mostly lands on the symbol and the search's unpredictable branches are skipped.
class SymbolModel {
 public:
  explicit SymbolModel(uint32_t symbols) : symbols_(symbols), last_(symbols - 1) {
    if (symbols < 2 || symbols > 2048) throw std::logic_error("laz: a symbol model has 2 to 2048 symbols");
    if (symbols > 16) {
      uint32_t bits = 3;
      while (2 * symbols > (1u << bits) && bits < kSymbolLengthShift) ++bits;
      table_size_ = 1u << bits;
      table_shift_ = kSymbolLengthShift - bits;
      // value / (length >> 15) reaches up to 2^15 + 63 (length is at least 2^24), so the lookup's index and the
      // one after it may pass table_size_ by 63 >> table_shift_ + 1.
      table_.assign(table_size_ + 2 + (63u >> table_shift_), 0);
    }
    distribution_.assign(symbols, 0);
    counts_.assign(symbols, 1);
    update_cycle_ = symbols;
    update();
    until_update_ = update_cycle_ = (symbols + 6) >> 1;
  }

  void update() {
    if ((total_ += update_cycle_) > kSymbolMaxCount) {
      total_ = 0;
      for (uint32_t& c : counts_) total_ += (c = (c + 1) >> 1);
    }
    const uint32_t scale = 0x80000000u / total_;
    uint32_t sum = 0, s = 0;
    for (uint32_t k = 0; k < symbols_; ++k) {
      distribution_[k] = (scale * sum) >> (31 - kSymbolLengthShift);
      sum += counts_[k];
      if (table_size_ != 0)
        for (const uint32_t w = distribution_[k] >> table_shift_; s < w;) table_[++s] = k - 1;
    }
    if (table_size_ != 0) {
      table_[0] = 0;
      while (s + 1 < table_.size()) table_[++s] = symbols_ - 1;
    }
    update_cycle_ = (5 * update_cycle_) >> 2;
    const uint32_t max_cycle = (symbols_ + 6) << 3;
    if (update_cycle_ > max_cycle) update_cycle_ = max_cycle;
    until_update_ = update_cycle_;
  }

 private:
  friend class ArithmeticDecoder;
  uint32_t symbols_, last_;
  uint32_t total_ = 0, update_cycle_ = 0, until_update_ = 0;
  uint32_t table_size_ = 0, table_shift_ = 0;
  std::vector<uint32_t> distribution_, counts_, table_;
};

class ArithmeticDecoder {
 public:
  // Starts decoding the bytes [begin, end): the first four are the initial value.
  ArithmeticDecoder(const uint8_t* begin, const uint8_t* end) : at_(begin), end_(end) {
    for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | byte();
    if (value_ >= length_) throw LazError("the arithmetic-coded stream starts with an impossible value");
  }

  [[gnu::always_inline]] uint32_t decode_bit(BitModel& m) {
    const uint32_t x = m.zero_prob * (length_ >> kBitLengthShift);
    const uint32_t bit = value_ >= x;
    if (bit == 0) {
      length_ = x;
      ++m.zero_count;
    } else {
      value_ -= x;
      length_ -= x;
    }
    if (length_ < kMinLength) renormalise();
    if (--m.until_update == 0) m.update();
    return bit;
  }

  [[gnu::always_inline]] uint32_t decode_symbol(SymbolModel& m) {
    uint32_t sym, x, y = length_;
    if (m.table_size_ != 0) {
      const uint32_t dv = value_ / (length_ >>= kSymbolLengthShift);
      const uint32_t t = dv >> m.table_shift_;
      sym = m.table_[t];
      uint32_t n = m.table_[t + 1] + 1;
      while (n > sym + 1) {
        const uint32_t k = (sym + n) >> 1;
        if (m.distribution_[k] > dv) n = k;
        else sym = k;
      }
      x = m.distribution_[sym] * length_;
      if (sym != m.last_) y = m.distribution_[sym + 1] * length_;
    } else {
      x = sym = 0;
      length_ >>= kSymbolLengthShift;
      uint32_t n = m.symbols_, k = n >> 1;
      do {
        const uint32_t z = length_ * m.distribution_[k];
        if (z > value_) {
          n = k;
          y = z;
        } else {
          sym = k;
          x = z;
        }
      } while ((k = (sym + n) >> 1) != sym);
    }
    value_ -= x;
    length_ = y - x;
    if (length_ < kMinLength) renormalise();
    ++m.counts_[sym];
    if (--m.until_update_ == 0) m.update();
    return sym;
  }

  // `bits` (1 to 32) raw bits, equiprobable.
  uint32_t read_bits(uint32_t bits) {
    if (bits > 19) {
      const uint32_t low = read_raw(16);
      return (read_bits(bits - 16) << 16) | low;
    }
    return read_raw(bits);
  }
  uint32_t read_int() {
    const uint32_t low = read_raw(16);
    return (read_raw(16) << 16) | low;
  }

  // How many bytes were asked for past the end of the stream (a sound stream asks for none).
  size_t overrun() const { return overrun_; }

 private:
  uint32_t read_raw(uint32_t bits) {
    const uint32_t sym = value_ / (length_ >>= bits);
    if (sym >> bits) throw LazError("the arithmetic-coded stream holds an impossible value");
    value_ -= length_ * sym;
    if (length_ < kMinLength) renormalise();
    return sym;
  }

  uint8_t byte() {
    if (at_ < end_) return *at_++;
    ++overrun_;
    return 0;
  }

  void renormalise() {
    do value_ = (value_ << 8) | byte();
    while ((length_ <<= 8) < kMinLength);
  }

  const uint8_t* at_;
  const uint8_t* end_;
  uint32_t value_ = 0, length_ = kMaxLength;
  size_t overrun_ = 0;
};

// LASzip's integer corrector: a value is coded as prediction + c, where the bucket k of c (its bit length) is
// a symbol of one of `contexts` models, and c within its bucket is a symbol (k <= bits_high) or a symbol for
// its high bits plus raw low bits. `bits` (or `range`) bounds the values, which wrap modulo that range.
class IntegerDecoder {
 public:
  explicit IntegerDecoder(uint32_t bits = 16, uint32_t contexts = 1, uint32_t bits_high = 8, uint32_t range = 0)
      : bits_high_(bits_high) {
    if (range != 0) {
      corr_range_ = range;
      for (uint32_t r = range; r != 0; r >>= 1) ++corr_bits_;
      if (corr_range_ == (1u << (corr_bits_ - 1))) --corr_bits_;
      corr_min_ = -static_cast<int32_t>(corr_range_ / 2);
    } else if (bits != 0 && bits < 32) {
      corr_bits_ = bits;
      corr_range_ = 1u << bits;
      corr_min_ = -static_cast<int32_t>(corr_range_ / 2);
    } else {
      corr_bits_ = 32;
      corr_range_ = 0;
      corr_min_ = INT32_MIN;
    }
    bucket_.reserve(contexts);
    for (uint32_t i = 0; i < contexts; ++i) bucket_.emplace_back(corr_bits_ + 1);
    within_.resize(corr_bits_);
  }

  int32_t decode(ArithmeticDecoder& dec, int32_t prediction, uint32_t context = 0) {
    int32_t real = static_cast<int32_t>(static_cast<uint32_t>(prediction) + static_cast<uint32_t>(corrector(dec, context)));
    if (real < 0) real = static_cast<int32_t>(static_cast<uint32_t>(real) + corr_range_);
    else if (static_cast<uint32_t>(real) >= corr_range_) real = static_cast<int32_t>(static_cast<uint32_t>(real) - corr_range_);
    return real;
  }

  // The bucket of the last correction (its bit length), which later fields use as a context.
  uint32_t k() const { return k_; }

 private:
  int32_t corrector(ArithmeticDecoder& dec, uint32_t context) {
    k_ = dec.decode_symbol(bucket_[context]);
    if (k_ == 0) return static_cast<int32_t>(dec.decode_bit(zero_));
    if (k_ >= 32) return corr_min_;
    int32_t c;
    std::optional<SymbolModel>& within = within_[k_ - 1];
    if (!within) within.emplace(k_ <= bits_high_ ? 1u << k_ : 1u << bits_high_);
    if (k_ <= bits_high_) {
      c = static_cast<int32_t>(dec.decode_symbol(*within));
    } else {
      const uint32_t low_bits = k_ - bits_high_;
      const uint32_t high = dec.decode_symbol(*within);
      c = static_cast<int32_t>((high << low_bits) | dec.read_bits(low_bits));
    }
    // [0, 2^(k-1)) holds the negative corrections, [2^(k-1), 2^k) the positive ones.
    if (c >= (1 << (k_ - 1))) return static_cast<int32_t>(static_cast<uint32_t>(c) + 1u);
    return static_cast<int32_t>(static_cast<uint32_t>(c) - ((1u << k_) - 1));
  }

  uint32_t bits_high_;
  uint32_t corr_bits_ = 0, corr_range_ = 0;
  int32_t corr_min_ = 0;
  uint32_t k_ = 0;
  std::vector<SymbolModel> bucket_;
  BitModel zero_;
  // The model of each bucket's corrections, created on first use (a stream uses few buckets; a fresh model's
  // state is fixed, so creating it late decodes the same).
  std::vector<std::optional<SymbolModel>> within_;
};

}  // namespace mv::laz

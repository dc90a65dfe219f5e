// PLY value decoding: reading one scalar of the data, all the generic element walkers need to know of the
// format -- binary in either byte order, or ascii tokens parsed strictly. (The binary fast paths of the
// walker decode whole records from the buffer with decode() instead.) Internal to host/io; not a public API.
#pragma once
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

#include "ply_header.h"
#include "ply_source.h"

namespace mv::io::detail {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);

template <class T, bool Swap>
T load(const char* p) {
  using U = std::conditional_t<sizeof(T) == 1, uint8_t,
            std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  U u;
  std::memcpy(&u, p, sizeof u);
  if constexpr (Swap && sizeof(T) == 2) u = __builtin_bswap16(u);
  if constexpr (Swap && sizeof(T) == 4) u = __builtin_bswap32(u);
  if constexpr (Swap && sizeof(T) == 8) u = __builtin_bswap64(u);
  return std::bit_cast<T>(u);
}

// One binary value in file byte order; Swap when that differs from the host's. double holds every type exactly.
// Always inlined: the binary fast paths call it per value, and the switch then folds into their loops.
template <bool Swap>
[[gnu::always_inline]] inline double decode(const char* p, Scalar t) {
  switch (t) {
    case Scalar::i8: return load<int8_t, Swap>(p);
    case Scalar::u8: return load<uint8_t, Swap>(p);
    case Scalar::i16: return load<int16_t, Swap>(p);
    case Scalar::u16: return load<uint16_t, Swap>(p);
    case Scalar::i32: return load<int32_t, Swap>(p);
    case Scalar::u32: return load<uint32_t, Swap>(p);
    case Scalar::f32: return load<float, Swap>(p);
    case Scalar::f64: return load<double, Swap>(p);
  }
  return 0;
}

template <bool Swap>
class BinaryValues {
 public:
  static constexpr bool kSwap = Swap;
  static constexpr bool kBinary = true;
  explicit BinaryValues(Source& src) : src_(src) {}

  double scalar(Scalar t) { return decode<Swap>(src_.take(scalar_size(t)), t); }
  void skip(Scalar t, uint64_t n) { src_.skip(sat_mul(n, scalar_size(t))); }
  std::string where() const { return {}; }

 private:
  Source& src_;
};

// Ascii values; the parsers are in ply_values.cpp.
class AsciiValues {
 public:
  static constexpr bool kBinary = false;
  explicit AsciiValues(Source& src) : src_(src) {}

  double scalar(Scalar t) {
    std::string_view s = src_.token();
    return is_integer(t) ? parse_integer(s, t) : parse_real(s, t);
  }
  // Skipped values are still checked: the format is strict.
  void skip(Scalar t, uint64_t n) {
    for (uint64_t i = 0; i < n; ++i) scalar(t);
  }
  std::string where() const { return "line " + num(src_.line()) + ": "; }

 private:
  double parse_integer(std::string_view s, Scalar t);
  double parse_real(std::string_view s, Scalar t);
  [[noreturn]] void bad(std::string_view s, Scalar t) const;

  Source& src_;
};

}  // namespace mv::io::detail

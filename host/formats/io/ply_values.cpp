// PLY ascii values (ply_values.h): integers and reals parsed strictly, each in the range of its PLY type.
#include "ply_values.h"

#include <charconv>
#include <cmath>
#include <system_error>

#include "megavox/error.h"

namespace mv::io::detail {

double AsciiValues::parse_integer(std::string_view s, Scalar t) {
  static constexpr int64_t lo[] = {INT8_MIN, 0, INT16_MIN, 0, INT32_MIN, 0};
  static constexpr int64_t hi[] = {INT8_MAX, UINT8_MAX, INT16_MAX, UINT16_MAX, INT32_MAX, UINT32_MAX};
  std::string_view digits = s.size() > 1 && s[0] == '+' ? s.substr(1) : s;
  int64_t v = 0;
  auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  size_t i = static_cast<size_t>(t);
  if (ec != std::errc{} || end != digits.data() + digits.size() || v < lo[i] || v > hi[i]) bad(s, t);
  return static_cast<double>(v);
}

double AsciiValues::parse_real(std::string_view s, Scalar t) {
  std::string_view digits = s.size() > 1 && s[0] == '+' ? s.substr(1) : s;
  double v = 0;
  auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  // Out-of-range values become +-inf so that the caller reports them as non-finite.
  if (ec == std::errc::result_out_of_range) v = digits[0] == '-' ? -HUGE_VAL : HUGE_VAL;
  else if (ec != std::errc{}) bad(s, t);
  if (end != digits.data() + digits.size()) bad(s, t);
  return v;
}

void AsciiValues::bad(std::string_view s, Scalar t) const {
  throw Error(src_.path() + ": " + where() + "'" + std::string(s) + "' is not a valid " + std::string(scalar_name(t)));
}

}  // namespace mv::io::detail

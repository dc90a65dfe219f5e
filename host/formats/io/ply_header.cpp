#include "ply_header.h"

#include <algorithm>
#include <charconv>
#include <utility>

#include "megavox/error.h"

namespace mv::io::detail {

// ---------------------------------------------------------------------------------------------------
// Types

size_t scalar_size(Scalar t) {
  static constexpr size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return sizes[static_cast<size_t>(t)];
}

bool is_integer(Scalar t) { return t < Scalar::f32; }

std::string_view scalar_name(Scalar t) {
  static constexpr std::string_view names[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  return names[static_cast<size_t>(t)];
}

std::optional<Scalar> parse_scalar(std::string_view s) {
  static constexpr std::pair<std::string_view, Scalar> names[] = {
      {"char", Scalar::i8},     {"int8", Scalar::i8},     {"uchar", Scalar::u8},    {"uint8", Scalar::u8},
      {"short", Scalar::i16},   {"int16", Scalar::i16},   {"ushort", Scalar::u16},  {"uint16", Scalar::u16},
      {"int", Scalar::i32},     {"int32", Scalar::i32},   {"uint", Scalar::u32},    {"uint32", Scalar::u32},
      {"float", Scalar::f32},   {"float32", Scalar::f32}, {"double", Scalar::f64},  {"float64", Scalar::f64}};
  for (const auto& [name, t] : names)
    if (name == s) return t;
  return std::nullopt;
}

std::string format_name(Format f) {
  switch (f) {
    case Format::ascii: return "ascii";
    case Format::binary_le: return "binary_little_endian";
    case Format::binary_be: return "binary_big_endian";
  }
  return {};
}

// ---------------------------------------------------------------------------------------------------
// Parser

namespace {

constexpr uint64_t kMaxHeaderBytes = 1 << 20;  // real headers are a few hundred bytes

std::vector<std::string_view> split_words(std::string_view s) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < s.size()) {
    if (s[i] == ' ' || s[i] == '\t') {
      ++i;
      continue;
    }
    size_t j = s.find_first_of(" \t", i);
    if (j == std::string_view::npos) j = s.size();
    words.push_back(s.substr(i, j - i));
    i = j;
  }
  return words;
}

class HeaderParser {
 public:
  explicit HeaderParser(HeaderLines& src) : src_(src) {}

  Header parse() {
    std::string text;
    if (!first_line_is_ply(text)) throw Error(src_.path() + ": not a PLY file (the first line is not 'ply')");
    try {
      while (true) {
        line_ = src_.line();
        if (!src_.header_line(text, kMaxHeaderBytes) || src_.consumed() > kMaxHeaderBytes)
          fail("header longer than " + num(kMaxHeaderBytes) + " bytes (no end_header?)");
        if (parse_line(text)) break;
      }
    } catch (const EndOfData&) {
      throw Error(src_.path() + ": header ends at line " + num(src_.line()) + " without 'end_header'");
    }
    if (!have_format_) fail("header has no 'format' line");
    return std::move(h_);
  }

 private:
  bool first_line_is_ply(std::string& text) {
    try {
      return src_.header_line(text, 4) && text == "ply";
    } catch (const EndOfData&) {
      return false;
    }
  }

  // True at end_header.
  bool parse_line(std::string_view text) {
    auto w = split_words(text);
    if (w.empty()) fail("empty header line");
    if (w[0] == "comment") {
      std::string_view rest = text.substr(text.find("comment") + 7);
      h_.comments.emplace_back(rest.substr(std::min(rest.find_first_not_of(" \t"), rest.size())));
    } else if (w[0] == "obj_info") {
      // Free-form, nothing to keep.
    } else if (w[0] == "format") {
      parse_format(w);
    } else if (!have_format_) {
      fail("expected the 'format' line before '" + std::string(w[0]) + "'");
    } else if (w[0] == "element") {
      parse_element(w);
    } else if (w[0] == "property") {
      parse_property(w);
    } else if (w[0] == "end_header") {
      if (w.size() != 1) fail("unexpected text after 'end_header'");
      return true;
    } else {
      fail("unknown header keyword '" + std::string(w[0]) + "'");
    }
    return false;
  }

  void parse_format(const std::vector<std::string_view>& w) {
    if (have_format_) fail("second 'format' line");
    if (w.size() != 3) fail("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
    if (w[1] == "ascii") h_.format = Format::ascii;
    else if (w[1] == "binary_little_endian") h_.format = Format::binary_le;
    else if (w[1] == "binary_big_endian") h_.format = Format::binary_be;
    else fail("unknown format '" + std::string(w[1]) + "'");
    if (w[2] != "1.0") fail("unsupported PLY version '" + std::string(w[2]) + "' (only 1.0)");
    have_format_ = true;
  }

  void parse_element(const std::vector<std::string_view>& w) {
    if (w.size() != 3) fail("expected 'element <name> <count>'");
    uint64_t count = 0;
    auto [end, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
    if (ec != std::errc{} || end != w[2].data() + w[2].size())
      fail("element count '" + std::string(w[2]) + "' is not a number from 0 to 2^64-1");
    for (const Element& e : h_.elements)
      if (e.name == w[1]) fail("duplicate element '" + e.name + "'");
    h_.elements.push_back({std::string(w[1]), count, {}, line_});
  }

  void parse_property(const std::vector<std::string_view>& w) {
    if (h_.elements.empty()) fail("property before any element");
    Property p;
    p.line = line_;
    if (w.size() >= 2 && w[1] == "list") {
      if (w.size() != 5) fail("expected 'property list <count type> <value type> <name>'");
      p.is_list = true;
      p.count_type = type(w[2]);
      if (!is_integer(p.count_type)) fail("list count type must be an integer type, not '" + std::string(w[2]) + "'");
      p.type = type(w[3]);
      p.name = w[4];
    } else {
      if (w.size() != 3) fail("expected 'property <type> <name>'");
      p.type = type(w[1]);
      p.name = w[2];
    }
    Element& e = h_.elements.back();
    for (const Property& q : e.props)
      if (q.name == p.name) fail("duplicate property '" + p.name + "' in element '" + e.name + "'");
    e.props.push_back(std::move(p));
  }

  Scalar type(std::string_view s) {
    auto t = parse_scalar(s);
    if (!t) fail("unknown property type '" + std::string(s) + "'");
    return *t;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(src_.path() + ": line " + num(line_) + ": " + what);
  }

  HeaderLines& src_;
  Header h_;
  bool have_format_ = false;
  uint64_t line_ = 1;
};

}  // namespace

Header parse_header(HeaderLines& in) { return HeaderParser(in).parse(); }

std::string plural(const Element& e) {
  return e.name == "vertex" ? "vertices" : e.name == "face" ? "faces" : "'" + e.name + "' elements";
}

uint64_t element_offset(const Header& h, size_t element, uint64_t header_bytes) {
  if (h.format == Format::ascii) return 0;
  uint64_t at = header_bytes;
  for (size_t k = 0; k < element && k < h.elements.size(); ++k) {
    uint64_t entry = 0;
    for (const Property& p : h.elements[k].props) {
      if (p.is_list) return 0;
      entry += scalar_size(p.type);
    }
    at += entry * h.elements[k].count;
  }
  return at;
}

void check_counts(const Header& h, const std::string& path, uint64_t data_bytes, size_t elements) {
  const bool ascii = h.format == Format::ascii;
  const uint64_t available = data_bytes + (ascii ? 1 : 0);  // ascii: the last value may lack its "\n"
  uint64_t need = 0;
  for (size_t i = 0; i < h.elements.size() && i < elements; ++i) {
    const Element& e = h.elements[i];
    uint64_t per_entry = 0;
    for (const Property& p : e.props) per_entry += ascii ? 2 : scalar_size(p.is_list ? p.count_type : p.type);
    uint64_t total = sat_add(need, sat_mul(per_entry, e.count));
    if (total > available)
      throw Error(path + ": truncated: expected " + num(e.count) + " " + plural(e) + ", but the " + num(data_bytes) +
                  " bytes after the header hold at most " + num((available - need) / per_entry));
    need = total;
  }
}

}  // namespace mv::io::detail

// PLY header: scalar types, element and property descriptions, and the parser that reads and validates the
// header lines of a PLY 1.0 file. Internal to host/io (used by the PLY reader); not a public API.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/header_numbers.h"

namespace mv::io::detail {

// ---------------------------------------------------------------------------------------------------
// Types

enum class Scalar : uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

size_t scalar_size(Scalar t);
bool is_integer(Scalar t);
std::string_view scalar_name(Scalar t);  // the PLY name: "char", "uchar", ... "double"
std::optional<Scalar> parse_scalar(std::string_view s);  // either spelling: "uchar" or "uint8"

struct Property {
  std::string name;
  bool is_list = false;
  Scalar count_type = Scalar::u8;  // lists only
  Scalar type = Scalar::f32;       // the value type (of each list entry for lists)
  uint64_t line = 0;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
  uint64_t line = 0;
};

enum class Format { ascii, binary_le, binary_be };

std::string format_name(Format f);  // as on the format line: "ascii", "binary_little_endian", ...

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::vector<std::string> comments;
};


// ---------------------------------------------------------------------------------------------------
// Parser

// Thrown when the data ends early; whoever knows which element was being read turns it into mv::Error.
struct EndOfData {};

// Where the header parser reads its lines from (the reader's buffered file).
class HeaderLines {
 public:
  virtual const std::string& path() const = 0;
  virtual uint64_t consumed() const = 0;  // bytes read from the start of the file
  virtual uint64_t line() const = 0;      // the line being read, 1-based
  // One header line without "\n" or "\r\n". False if it is longer than max_chars; throws EndOfData at the end.
  virtual bool header_line(std::string& out, size_t max_chars) = 0;

 protected:
  ~HeaderLines() = default;
};

// Reads the header from the start of `in` up to and including its "end_header" line; throws mv::Error
// naming the file, the line and the fault on anything malformed.
Header parse_header(HeaderLines& in);

// "vertices", "faces" or "'<name>' elements", for messages.
std::string plural(const Element& e);

// Refuses counts the data could not hold, before anything is allocated (a truncated file or a garbage count):
// throws mv::Error naming `path` unless the `data_bytes` after the header can hold the first `elements`
// elements, each entry at least its scalars and list counts (binary) or 2 characters per value, "0 " (ascii).
void check_counts(const Header& h, const std::string& path, uint64_t data_bytes, size_t elements = SIZE_MAX);

// The byte where element `element`'s first entry starts, for seeking to it: a binary file whose elements before
// it have entries of scalars alone (fixed size), `header_bytes` after the header's start; 0 otherwise.
uint64_t element_offset(const Header& h, size_t element, uint64_t header_bytes);

}  // namespace mv::io::detail

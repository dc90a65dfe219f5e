// megavox — the bytes ranks send each other (megavox/rank_collectives.h): values, arrays and text written in
// order and read back in order, each read checked against the message's end. Both ends run the same binary, so
// values go as their bytes.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "megavox/error.h"

namespace mv {

struct MessageWriter {
  std::vector<uint8_t> bytes;
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof v);
  }
  // The count, then the values.
  template <class T>
  void put_all(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<uint64_t>(v.size());
    const auto* p = reinterpret_cast<const uint8_t*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
  }
  void put_text(const std::string& s) {
    put<uint64_t>(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
};

struct MessageReader {
  const uint8_t* at;
  const uint8_t* end;
  explicit MessageReader(const std::vector<uint8_t>& b) : at(b.data()), end(b.data() + b.size()) {}
  uint64_t left() const { return static_cast<uint64_t>(end - at); }
  void need(uint64_t n) const {
    if (n > left()) throw Error("internal error: a message from another rank is cut short");
  }
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  void get_all(std::vector<T>& v) {
    const uint64_t n = get<uint64_t>();
    need(n * sizeof(T));
    v.resize(n);
    std::memcpy(v.data(), at, n * sizeof(T));
    at += n * sizeof(T);
  }
  std::string text() {
    const uint64_t n = get<uint64_t>();
    need(n);
    std::string s(reinterpret_cast<const char*>(at), n);
    at += n;
    return s;
  }
};

}  // namespace mv

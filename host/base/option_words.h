// The library's messages name options as the CLI spells them ("raise --cube", "over --memory"): the checks
// that word them serve every front end. A front end whose options have other names (the C API's fields, the
// service's JSON keys) rewords the names it knows rather than repeat a check to word it differently.
#pragma once
#include <cctype>
#include <span>
#include <string>
#include <string_view>

namespace mv {

struct OptionWords {
  std::string_view from;  // a name as it appears in messages: "--cube"
  std::string_view to;    // the front end's name for it
};

// `message` with each whole-word occurrence of a `from` replaced by its `to` (the first entry that matches
// wins); a name inside a longer word ("--cubes", "a--cube") is left alone, as is everything else.
inline std::string reword_options(std::string_view message, std::span<const OptionWords> words) {
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; };
  std::string out;
  out.reserve(message.size());
  for (size_t i = 0; i < message.size();) {
    const OptionWords* hit = nullptr;
    if (i == 0 || !word_char(message[i - 1]))
      for (const OptionWords& w : words) {
        const size_t end = i + w.from.size();
        if (message.substr(i, w.from.size()) == w.from && (end == message.size() || !word_char(message[end]))) {
          hit = &w;
          break;
        }
      }
    if (hit) {
      out += hit->to;
      i += hit->from.size();
    } else {
      out += message[i++];
    }
  }
  return out;
}

}  // namespace mv

// "Did you mean": when the parser refuses a command line, the verb or option it could not place and the
// nearest name the command knows, so a typo gets an answer instead of a usage dump.
#pragma once
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace mv::cli {

// Walks argv as `app` would, down through its verbs: at the first word that is neither a verb where one is
// expected nor an option of the verb reached (or of the verbs above it), a message naming that word and, when one
// is close, the name meant. Nothing when every word is known (the parser's own message then says more).
std::optional<std::string> diagnose_unknown_word(const CLI::App& app, int argc, const char* const* argv);

// The edit distance (insertions, deletions, substitutions, swaps of neighbours) between two words.
size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace mv::cli

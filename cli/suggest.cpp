#include "suggest.h"

#include <algorithm>
#include <vector>

namespace mv::cli {

size_t edit_distance(const std::string& a, const std::string& b) {
  // Optimal string alignment: a swap of two neighbouring letters, the commonest typo, counts as one edit.
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

namespace {

// The candidate nearest `word`, if near enough to be a typo of it (a third of its letters, at least two).
std::optional<std::string> nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_distance) best = c, best_distance = d;
  }
  return best;
}

std::string joined(const std::vector<std::string>& words) {
  std::string s;
  for (const std::string& w : words) s += (s.empty() ? "" : ", ") + w;
  return s;
}

// The command as typed so far: "build", "bench sort"; empty at the top.
std::string path_of(const CLI::App* cmd) {
  std::string path;
  for (; cmd && cmd->get_parent(); cmd = cmd->get_parent()) path = cmd->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

// The option `name` ("--x", "-x") of `cmd` or of the commands above it (options fall through to the parents).
const CLI::Option* find_option(const CLI::App* cmd, const std::string& name) {
  for (; cmd; cmd = cmd->get_parent())
    if (const CLI::Option* o = cmd->get_option_no_throw(name)) return o;
  return nullptr;
}

std::vector<std::string> option_names(const CLI::App* cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* o : cmd->get_options()) {
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
    for (const std::string& s : o->get_snames()) names.push_back("-" + s);
  }
  return names;
}

}  // namespace

std::optional<std::string> diagnose_unknown_word(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* cmd = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--") return std::nullopt;  // the rest are positional values
    if (word.size() > 1 && word[0] == '-' && !(word[1] >= '0' && word[1] <= '9') && word[1] != '.') {
      const std::string name = word.substr(0, word.find('='));
      const CLI::Option* o = find_option(cmd, name);
      if (!o && name.size() > 2 && name[1] != '-') o = find_option(cmd, name.substr(0, 2));  // -q1: -q and a value
      if (!o) {
        const std::string where = cmd == &app ? "megavox" : "megavox " + path_of(cmd);
        std::string message = "unknown option '" + name + "' for '" + where + "'";
        if (auto meant = nearest(name, option_names(cmd))) message += "; did you mean '" + *meant + "'?";
        else message += " (see '" + where + " --help')";
        return message;
      }
      // An option that takes a value and was not given one with '=' takes the next word.
      if (o->get_type_size_max() > 0 && name == word && name.size() > 1 && (name[1] == '-' || name.size() == 2)) ++i;
      continue;
    }
    std::vector<std::string> verbs;
    for (const CLI::App* sub : cmd->get_subcommands([](const CLI::App*) { return true; })) verbs.push_back(sub->get_name());
    if (verbs.empty()) continue;  // a positional value of the verb reached
    if (std::find(verbs.begin(), verbs.end(), word) != verbs.end()) {
      cmd = cmd->get_subcommand(word);
      continue;
    }
    if (cmd->get_require_subcommand_min() == 0) continue;  // a positional value beside optional verbs
    const std::string prefix = cmd == &app ? "" : path_of(cmd) + " ";
    std::string message = "unknown command '" + prefix + word + "'";
    if (auto meant = nearest(word, verbs)) message += "; did you mean '" + prefix + *meant + "'?";
    else message += " (commands: " + joined(verbs) + ")";
    return message;
  }
  return std::nullopt;
}

}  // namespace mv::cli

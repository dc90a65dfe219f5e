#include "serve/job_words.h"

#include <cctype>
#include <cstring>

namespace mv::serve {

namespace {

struct Word {
  const char* flag;  // without the dashes
  const char* words;
};

// Flags the library's messages name, and what a job's client reads instead.
const Word kWords[] = {
    {"cube", "\"cube\""},
    {"resolution", "\"resolution\""},
    {"format", "\"format\""},
    {"voxelize", "\"voxelize\""},
    {"grid-origin", "\"grid_origin\""},
    {"width", "\"width\""},
    {"height", "\"height\""},
    {"view", "\"view\""},
    {"shading", "\"shading\""},
    {"eye", "\"eye\""},
    {"target", "\"target\""},
    {"up", "\"up\""},
    {"fov", "\"fov\""},
    {"depth", "\"depth\""},
    {"max-node-points", "\"max_node_points\""},
    {"rect", "\"rect\""},
    {"seeds", "\"seeds\""},
    {"model", "\"model\""},
    {"iterations", "\"iterations\""},
    {"erode", "\"erode\""},
    {"memory", "the server's host memory per job"},
    {"device-memory", "the server's device memory per job"},
};

bool flag_char(char c) { return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '-'; }

}  // namespace

std::string in_job_terms(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  for (size_t i = 0; i < message.size();) {
    // a flag: "--" at the start of a word, then lower-case letters, digits and dashes
    if (message.compare(i, 2, "--") == 0 && (i == 0 || !flag_char(message[i - 1]))) {
      size_t end = i + 2;
      while (end < message.size() && flag_char(message[end])) ++end;
      while (end > i + 2 && message[end - 1] == '-') --end;
      const std::string flag = message.substr(i + 2, end - i - 2);
      const char* words = nullptr;
      for (const Word& w : kWords)
        if (flag == w.flag) words = w.words;
      if (words) {
        out += words;
        i = end;
        continue;
      }
    }
    out += message[i++];
  }
  return out;
}

}  // namespace mv::serve

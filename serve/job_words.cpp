#include "job_words.h"

#include <cctype>
#include <string_view>

namespace mv::serve {

namespace {

struct Words {
  std::string_view from;  // the library's term, as it appears in messages
  std::string_view to;    // the service's name for it
};

// Longer terms first where one holds another.
const Words kWords[] = {
    {"the cube size", "\"cube\""},
    {"the resolution", "\"resolution\""},
    {"the encoding", "\"format\""},
    {"the point output format", "\"format\""},
    {"the voxelization rule", "\"voxelize\""},
    {"the grid origin", "\"grid_origin\""},
    {"the picture width", "\"width\""},
    {"the box", "\"rect\""},
    {"the field of view", "\"fov\""},
    {"the depth", "\"depth\""},
    {"the node point limit", "\"max_node_points\""},
    {"the host memory budget", "the server's host memory per job"},
    {"the device memory budget", "the server's device memory per job"},
};

bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; }

}  // namespace

// Each whole-word occurrence of a term is replaced (the first that matches wins); a term inside a longer word
// is left alone, as is everything else.
std::string in_job_terms(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  for (size_t i = 0; i < message.size();) {
    const Words* hit = nullptr;
    if (i == 0 || !word_char(message[i - 1]))
      for (const Words& w : kWords) {
        const size_t end = i + w.from.size();
        if (std::string_view(message).substr(i, w.from.size()) == w.from &&
            (end == message.size() || !word_char(message[end]))) {
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

}  // namespace mv::serve

// The notice a first run on a device gives while its kernels compile (seconds to a minute on PoCL), so the
// wait is not silent: one line saying why, then a line naming the program compiling, erased when it is done.
#include <cstdio>

#include "cli_common.h"

namespace mv::cli {

CompileListener compile_notice(bool enabled) {
  if (!enabled) return {};
  return [](const CompileEvent& e) {
    // Each line starts by erasing what the command had drawn on it (its progress bar), which redraws after.
    if (e.done) {
      std::fprintf(stderr, "\r\033[2K");
    } else {
      if (e.count == 1)
        std::fprintf(stderr, "\r\033[2Kmegavox: compiling kernels for %s (first use; cached for later runs)\n",
                     e.device.c_str());
      std::fprintf(stderr, "\r\033[2Kkernels   compiling %u: %s", e.count, e.program.c_str());
    }
    std::fflush(stderr);
  };
}

}  // namespace mv::cli

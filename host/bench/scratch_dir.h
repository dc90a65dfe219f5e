// A fresh folder in $TMPDIR (or /tmp) for what a benchmark writes and does not keep (the .mvx it builds, the
// peer's outputs); removed with everything in it on destruction.
#pragma once
#include <string>

namespace mv::bench {

class ScratchDir {
 public:
  ScratchDir();  // throws mv::Error when no folder can be made
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string file(const std::string& name) const { return dir_ + "/" + name; }

 private:
  std::string dir_;
};

}  // namespace mv::bench

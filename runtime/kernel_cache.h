// Compiled kernels kept on disk between runs, so only a device's first use pays for compiling them (PoCL took
// 5 s for a 64^3 build's programs on a cold cache, 0.3 s warm). The runtime keeps its own cache rather than
// relying on a driver's alone: a driver's cache cannot be asked whether it holds a program, and the caller is
// told when a compile is about to happen (DeviceOptions::on_compile).
#pragma once
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

namespace mv::rt {

// A folder of compiled program binaries (OpenCL), or of records that the driver compiled a pipeline and keeps it
// in its own cache (Vulkan: Mesa's shader cache; lavapipe took 240 s for a 64^3 build's pipelines with that
// cache empty, 1.7 s with it warm), one file per key. Best effort: a folder that cannot be made or
// written leaves every lookup a miss, and a torn or foreign file is the backend's to reject (then rebuilt).
class KernelCache {
 public:
  // `dir` empty: the default folder (default_dir()).
  explicit KernelCache(std::string dir);

  // $MEGAVOX_KERNEL_CACHE, else $XDG_CACHE_HOME/megavox/kernels, else $HOME/.cache/megavox/kernels; empty when
  // none of them is set.
  static std::string default_dir();

  // A file name for what identifies a compiled program: its source, build options and the device and driver.
  static std::string key(std::initializer_list<std::string_view> parts);

  bool contains(const std::string& key) const;
  std::optional<std::string> load(const std::string& key) const;
  // Written to a file of this process's own and renamed into place, so concurrent runs never see half a file.
  void store(const std::string& key, std::string_view bytes) const;

  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
};

}  // namespace mv::rt

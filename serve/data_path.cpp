#include "data_path.h"

#include <filesystem>

#include "serve_error.h"

namespace mv::serve {

std::string resolve_data_path(const std::string& data_dir, const std::string& name, const std::string& key) {
  namespace fs = std::filesystem;
  const std::string shown = name.substr(0, 200);
  if (name.empty()) throw ServeError(key + ": no file named");
  if (name.find('\0') != std::string::npos) throw ServeError(key + ": a NUL byte in the file name");
  const fs::path rel(name);
  if (rel.is_absolute()) throw ServeError(key + " '" + shown + "': give a path relative to the data folder");
  for (const auto& part : rel)
    if (part == "..") throw ServeError(key + " '" + shown + "': \"..\" is refused (paths stay inside the data folder)");
  std::error_code ec;
  const fs::path root = fs::canonical(data_dir, ec);
  if (ec) throw ServeError("the data folder " + data_dir + " cannot be read: " + ec.message(), MV_ERROR_IO);
  const fs::path full = fs::weakly_canonical(root / rel, ec);  // resolves links that exist
  if (ec) throw ServeError(key + " '" + shown + "': " + ec.message());
  auto r = root.begin();
  auto f = full.begin();
  for (; r != root.end(); ++r, ++f)
    if (f == full.end() || *f != *r) throw ServeError(key + " '" + shown + "' leads outside the data folder");
  if (!fs::is_regular_file(full, ec)) throw ServeError(key + " '" + shown + "': no such file in the data folder");
  return full.string();
}

}  // namespace mv::serve

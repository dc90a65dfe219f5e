// Files a job names live under --data-dir: a name is resolved there, and refused when it leads outside
// (absolute paths, "..", symbolic links pointing out).
#pragma once
#include <string>

namespace mv::serve {

// The file `name` under `data_dir` (an existing folder). Throws ServeError naming the refusal and `key`, the
// job's field that named the file.
std::string resolve_data_path(const std::string& data_dir, const std::string& name, const std::string& key = "input");

}  // namespace mv::serve

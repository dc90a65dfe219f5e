// Output folders (a 3D Tiles tileset: one JSON file and a file per node) are written into a temporary folder
// beside DIR and swapped in only when complete, so a failure leaves neither a half-written DIR nor a mix of
// old and new files.
#pragma once
#include <functional>
#include <string>

namespace mv::io {

// Creates DIR.tmp-XXXXXX beside DIR, calls `write` with its path, then puts it in DIR's place. An existing DIR
// is replaced only when it is empty or holds `marker` (the file that says it is an earlier output of the same
// kind, e.g. "tileset.json"): any other folder is left alone and mv::Error says so, before anything is
// written. On any failure the temporary folder is removed and mv::Error names DIR (a process killed
// part-way can leave a DIR.tmp-XXXXXX behind: nothing reads it, and it can be deleted).
void write_dir_atomically(const std::string& dir, const std::string& marker,
                          const std::function<void(const std::string& tmp_dir)>& write);

// Whether `path` lies in a temporary folder this thread is writing with write_dir_atomically: its files are
// synced to disk together, once, before the folder takes its name (one sync per file would cost more than
// the writing for a tileset of thousands of tiles), so the file writer need not sync each.
bool in_folder_being_written(const std::string& path);

}  // namespace mv::io

// A 3D Tiles folder (tileset.json and its tiles) as one 3D Tiles archive (.3tz): a ZIP whose entries are
// stored uncompressed (the fastest to read, as the format advises) and end with the `@3dtilesIndex1@` index
// (MD5 of each path and its local header's offset, sorted) that readers use to find a tile without scanning
// the central directory.
#pragma once
#include <string>

namespace mv::serve {

// Writes every file under `dir` (paths relative to it, '/'-separated) into the archive `path`, written to a
// temporary name and renamed. Throws ServeError naming what failed.
void write_3tz(const std::string& dir, const std::string& path);

}  // namespace mv::serve

#include "io/vdb_grid_reader.h"

#include <openvdb/io/Archive.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>

#include <istream>
#include <map>
#include <memory>

#include "io/file_streambuf.h"

namespace mv::io {

namespace {

// OpenVDB's Archive with the protected steps its io::Stream constructor takes (header, stream metadata, grid
// count, then descriptor and grid in turn), stopping at the wanted grid.
class GridReader : public openvdb::io::Archive {
 public:
  openvdb::GridBase::Ptr read(std::istream& is, std::string& name) {
    readHeader(is);
    const bool has_offsets = inputHasGridOffsets();  // io::Stream writes none
    openvdb::io::setStreamMetadataPtr(is, metadata_, /*transfer=*/false);
    openvdb::io::setVersion(is, libraryVersion(), fileVersion());
    openvdb::io::setDataCompression(is, compression());
    openvdb::MetaMap().readMeta(is);
    const int32_t count = readGridCount(is);
    NamedGridMap read_grids;                      // an instance's parent comes before it in the file
    std::map<std::string, std::streampos> skipped;  // where the descriptors of the grids skipped start
    for (int32_t i = 0; i < count; ++i) {
      const std::streampos at = is.tellg();
      openvdb::io::GridDescriptor gd;
      openvdb::GridBase::Ptr grid = gd.read(is);
      const bool wanted = name.empty() || gd.gridName() == name || gd.uniqueName() == name;
      if (!wanted && has_offsets && !gd.isInstance()) {
        skipped[gd.uniqueName()] = at;
        gd.seekToEnd(is);
        continue;
      }
      readGrid(grid, gd, is);
      read_grids[gd.uniqueName()] = grid;
      if (!wanted) continue;
      if (gd.isInstance() && !read_grids.count(gd.instanceParentName()) && skipped.count(gd.instanceParentName())) {
        is.seekg(skipped[gd.instanceParentName()]);  // the parent's tree, read now
        openvdb::io::GridDescriptor parent;
        openvdb::GridBase::Ptr tree_grid = parent.read(is);
        readGrid(tree_grid, parent, is);
        read_grids[parent.uniqueName()] = tree_grid;
      }
      if (gd.isInstance()) connectInstance(gd, read_grids);  // throws when there is no such parent
      name = gd.gridName();
      return grid;
    }
    return nullptr;
  }

 private:
  // The stream points at it while the grid is read (OpenVDB: "must remain valid until the file is closed").
  openvdb::io::StreamMetadata::Ptr metadata_ = std::make_shared<openvdb::io::StreamMetadata>();
};

}  // namespace

openvdb::GridBase::Ptr read_vdb_grid(const std::string& path, std::string& name) {
  FileStreambuf file(path);  // through the file layer: its read faults and memory files reach OpenVDB
  std::istream is(&file);
  is.exceptions(std::ios::failbit | std::ios::badbit);
  return GridReader().read(is, name);
}

}  // namespace mv::io

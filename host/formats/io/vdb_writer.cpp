#include "vdb_writer.h"

#include <openvdb/openvdb.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

#include <cstdio>
#include <string>

#include "common/morton.h"
#include "atomic_file.h"
#include "megavox/error.h"

namespace mv::io {

void write_voxel_grid(const std::string& path, const std::vector<uint64_t>& keys, const GridTransform& g, bool nano,
                      const std::vector<uint8_t>& rgb) {
  if (!rgb.empty() && rgb.size() != 3 * keys.size())
    throw Error(path + ": " + std::to_string(rgb.size() / 3) + " colours for " + std::to_string(keys.size()) + " voxels");
  openvdb::initialize();
  auto grid = openvdb::MaskGrid::create();
  grid->setName("voxels");
  auto xf = openvdb::math::Transform::createLinearTransform(g.voxel_size);
  xf->postTranslate(openvdb::Vec3d(g.origin[0] + 0.5 * g.voxel_size, g.origin[1] + 0.5 * g.voxel_size,
                                   g.origin[2] + 0.5 * g.voxel_size));
  grid->setTransform(xf);
  auto colour = openvdb::Vec3SGrid::create(openvdb::Vec3s(0, 0, 0));
  colour->setName("colour");
  colour->setTransform(xf->copy());
  colour->setGridClass(openvdb::GRID_UNKNOWN);
  {
    auto acc = grid->getAccessor();
    auto cacc = colour->getAccessor();
    for (size_t i = 0; i < keys.size(); ++i) {
      const uint64_t k = keys[i];
      const openvdb::Coord c(int(mv_morton3_64_axis(k, 0)), int(mv_morton3_64_axis(k, 1)), int(mv_morton3_64_axis(k, 2)));
      acc.setValueOn(c);
      if (!rgb.empty())
        cacc.setValueOn(c, openvdb::Vec3s(rgb[3 * i] / 255.0f, rgb[3 * i + 1] / 255.0f, rgb[3 * i + 2] / 255.0f));
    }
  }
  write_atomically_by_name(path, [&](const std::string& tmp) {
    if (nano) {
      std::vector<nanovdb::GridHandle<>> handles;
      handles.push_back(nanovdb::openToNanoVDB(*grid));
      if (!rgb.empty()) handles.push_back(nanovdb::openToNanoVDB(*colour));
      nanovdb::io::writeGrids(tmp, handles);
    } else {
      openvdb::GridCPtrVec grids{grid};
      if (!rgb.empty()) grids.push_back(colour);
      openvdb::io::File file(tmp);
      file.write(grids);
      file.close();
    }
  });
}

}  // namespace mv::io

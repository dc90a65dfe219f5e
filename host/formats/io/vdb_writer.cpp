#include "vdb_writer.h"

#include <openvdb/openvdb.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

#include <cstdio>

#include "common/morton.h"
#include "atomic_file.h"
#include "megavox/error.h"

namespace mv::io {

void write_voxel_grid(const std::string& path, const std::vector<uint64_t>& keys, const GridTransform& g, bool nano) {
  openvdb::initialize();
  auto grid = openvdb::MaskGrid::create();
  grid->setName("voxels");
  auto xf = openvdb::math::Transform::createLinearTransform(g.voxel_size);
  xf->postTranslate(openvdb::Vec3d(g.origin[0] + 0.5 * g.voxel_size, g.origin[1] + 0.5 * g.voxel_size,
                                   g.origin[2] + 0.5 * g.voxel_size));
  grid->setTransform(xf);
  {
    auto acc = grid->getAccessor();
    for (uint64_t k : keys) {
      acc.setValueOn(openvdb::Coord(int(mv_morton3_64_axis(k, 0)), int(mv_morton3_64_axis(k, 1)),
                                    int(mv_morton3_64_axis(k, 2))));
    }
  }
  write_atomically_by_name(path, [&](const std::string& tmp) {
    if (nano) {
      nanovdb::io::writeGrid(tmp, nanovdb::openToNanoVDB(*grid));
    } else {
      openvdb::io::File file(tmp);
      file.write(openvdb::GridCPtrVec{grid});
      file.close();
    }
  });
}

}  // namespace mv::io

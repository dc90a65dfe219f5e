#!/usr/bin/env bash
# Sets up, builds and runs megavox's main job on its default input, the Stanford bunny (npm package `bunny`):
# list the compute devices, voxelize the bunny at 2K^3 and reduce it to a voxel DAG (.mvx), check the file,
# render it to a PNG through the ray traversal kernel, build an LOD point hierarchy of its vertices (OMiCroN)
# and splat it to a PNG, then benchmark the traversal against Embree on the
# triangles and the radix sort every stage builds on against std::sort and a parallel CPU sort.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --bench
scripts/build.sh -DMEGAVOX_BASELINES=AUTO
scripts/bunny.sh
build/megavox devices
build/megavox build build/bunny.ply --resolution 2K --format ssvdag -o build/bunny.mvx
build/megavox info build/bunny.mvx
build/megavox render build/bunny.mvx -o build/bunny.png
echo "picture: $(pwd)/build/bunny.png"
# The bunny's vertices as a point cloud: an LOD point hierarchy, checked, and a picture of it.
build/megavox points build build/bunny.ply -o build/bunny_points.mvx --max-node-points 256
build/megavox points info build/bunny_points.mvx
build/megavox points render build/bunny_points.mvx -o build/bunny_points.png
echo "picture: $(pwd)/build/bunny_points.png"
# The traversal kernel's rays/s against Embree on the bunny's triangles, then the sort every stage builds on.
build/megavox bench trace build/bunny.mvx --mesh build/bunny.ply --repeats 3
build/megavox bench sort --n 16M

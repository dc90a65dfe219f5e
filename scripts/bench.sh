#!/usr/bin/env bash
# Runs every benchmark BENCHMARKS.md reports, one after another (nothing else should run meanwhile), and
# prints each command with its JSON. Usage: scripts/bench.sh [out.jsonl]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --bench
scripts/build.sh -DMEGAVOX_BASELINES=AUTO >/dev/null
# bench build's peer, voxcom: built once into build/peers/voxcom (about 5 minutes) when the shared folder has it.
peer=../shared/peers/voxcom
if [[ ! -x build/peers/voxcom/voxelizer ]]; then
  if [[ -d $peer ]]; then bash "$peer/build.sh" build/peers/voxcom >&2
  else echo "bench: no $peer here, so bench build runs without its peer (voxcom)" >&2; fi
fi
out=${1:-/dev/null}
# The test data: $MEGAVOX_TEST_DATA, or the shared folder beside the checkout.
data=${MEGAVOX_TEST_DATA:-../shared/data}
: >"$out"
run() {
  echo "\$ $*" >&2
  "$@" | tee -a "$out"
}
for dev in ocl:0 vk:0; do
  for n in 1M 16M; do run build/megavox --device "$dev" bench sort --n "$n" --json; done
done
run build/megavox --device ocl:0 bench sort --n 64M --json
# 64M pairs need 1.5 GiB of keys, values and scratch: more than lavapipe's default budget (3/4 of 2 GiB).
run build/megavox --device vk:0 --device-memory 1600M bench sort --n 64M --repeats 1 --json
# The work-group-cooperative variant (Auto picks it on GPUs only) on lavapipe, for the record.
run build/megavox --device vk:0 bench sort --n 1M --strategy cooperative --json
# Ray traversal: the bunny built as svdag and ssvdag, traced on both devices against Embree on its triangles.
scripts/bunny.sh
build/megavox build build/bunny.ply --resolution 2K --format svdag -o build/bunny_svdag.mvx >/dev/null
build/megavox build build/bunny.ply --resolution 2K --format ssvdag -o build/bunny_ssvdag.mvx >/dev/null
run build/megavox --device ocl:0 bench trace build/bunny_svdag.mvx build/bunny_ssvdag.mvx --mesh build/bunny.ply --json
run build/megavox --device vk:0 bench trace build/bunny_svdag.mvx build/bunny_ssvdag.mvx --mesh build/bunny.ply --repeats 3 --json
# The build beside its peer at 2K: thin rule, grid at the min corner (voxcom's), the SSVDAG.
for mesh in "$data"/meshes_stanford/stanford_bunny.ply "$data"/meshes_misc/koala.ply; do
  if [[ -f $mesh ]]; then
    run build/megavox --device ocl:0 bench build "$mesh" --resolution 2K --voxelize thin --grid-origin min --format ssvdag --json
  fi
done
# Point clouds: the shared clouds and 100M points sampled from igea (about 4 minutes and 9 GiB of RAM).
clouds=()
for c in "$data"/pointcloud_autzen/autzen_trim.las "$data"/pointcloud_lion_takanawa/lion_takanawa.ply; do
  [[ -f $c ]] && clouds+=("$c")
done
igea="$data"/meshes_misc/igea.ply
if [[ -f $igea ]]; then
  run build/megavox --device ocl:0 bench points "${clouds[@]}" --sample-mesh "$igea" --sample-points 100M --json
elif ((${#clouds[@]})); then
  run build/megavox --device ocl:0 bench points "${clouds[@]}" --json
fi
# Voxel colours on the shared coloured clouds, both backends (about a minute).
if [[ -d $data/pointcloud_autzen ]]; then
  for dev in ocl:0 vk:0; do run build/megavox --device "$dev" bench attributes --data "$data" --json; done
fi
# ... and on a textured mesh (assimp-testmodels, installed by setup.sh --bench).
truck=/usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf
if [[ -f $truck ]]; then
  for dev in ocl:0 vk:0; do run build/megavox --device "$dev" bench attributes "$truck" --json; done
fi

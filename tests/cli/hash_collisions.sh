#!/usr/bin/env bash
# DAG reduction when node hashes collide. 64-bit hashes never collide in a test, so MEGAVOX_TEST_HASH_BITS
# keeps only a few bits of the first seed's hashes: every level then meets collisions and retries with the next
# seed. One process: the same nodes and voxels as with whole hashes, in core and in cubes, every encoding.
# Over MPI ranks (this machine only: shared memory and loopback): a collision between nodes of different ranks
# (each rank's own nodes distinct) is found by the keys' owners, and the bytes are those of one process.
# Usage: hash_collisions.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"

write_sphere_ply "$dir/sphere.ply" 40
# voxels FILE: the .mvx's voxels as a PLY of voxel centres; nodes FILE: its DAG nodes per level.
voxels() { "$megavox" export "$1" --format ply -o "$1.ply" > /dev/null && cat "$1.ply"; }
nodes() { "$megavox" info "$1" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["nodes_per_level"])'; }

for format in svdag ussvdag ssvdag; do
  for cube in 0 32; do
    args=(build "$dir/sphere.ply" --resolution 128 --cube "$cube" --format "$format" -q)
    "$megavox" "${args[@]}" -o "$dir/whole.mvx" > /dev/null
    MEGAVOX_TEST_HASH_BITS=4 "$megavox" "${args[@]}" -o "$dir/weak.mvx" > /dev/null 2> "$dir/weak.txt" ||
      fail "$format cube $cube, weak hashes: $(cat "$dir/weak.txt")"
    grep -q "seed 1 collided on one rank" "$dir/weak.txt" || fail "$format cube $cube: no collision met"
    [[ "$(nodes "$dir/whole.mvx")" == "$(nodes "$dir/weak.mvx")" ]] || fail "$format cube $cube: other nodes per level"
    cmp -s <(voxels "$dir/whole.mvx") <(voxels "$dir/weak.mvx") || fail "$format cube $cube: other voxels"
  done
done
# The retries are the same on every device.
weak=(build "$dir/sphere.ply" --resolution 128 --cube 32 --format ssvdag -q)
MEGAVOX_TEST_HASH_BITS=4 "$megavox" --device ocl:0 "${weak[@]}" -o "$dir/ocl.mvx" > /dev/null 2>&1
MEGAVOX_TEST_HASH_BITS=4 "$megavox" --device vk:0 "${weak[@]}" -o "$dir/vk.mvx" > /dev/null 2>&1
cmp -s "$dir/ocl.mvx" "$dir/vk.mvx" || fail "weak hashes: other bytes on vk:0 than on ocl:0"
bad=(build "$dir/sphere.ply" --resolution 64 -q -o "$dir/bad.mvx")
if MEGAVOX_TEST_HASH_BITS=65 "$megavox" "${bad[@]}" > "$dir/bad.txt" 2>&1; then
  fail "MEGAVOX_TEST_HASH_BITS=65 accepted"
fi
grep -q "not a bit count from 1 to 64" "$dir/bad.txt" || fail "no clear error: $(cat "$dir/bad.txt")"
[[ ! -e "$dir/bad.mvx" ]] || fail "output left after a refused hook"
echo "hash collisions: every encoding, in core and in cubes, retried to the same nodes and voxels; ocl:0 = vk:0"

mpi_test="hash collisions over ranks"
source "$(dirname "$0")/mpi_common.sh"
# 8 cubes of 64^3: each rank holds a few cube roots, distinct on the rank, whose few-bit keys meet only at their
# owners (these bit counts make it so for this sphere; the check below says when they no longer do).
for run in "svdag 3 2" "ssvdag 1 8"; do
  read -r format bits n <<< "$run"
  args=(build "$dir/sphere.ply" --resolution 128 --cube 64 --format "$format" -q)
  MEGAVOX_TEST_HASH_BITS=$bits "$megavox" "${args[@]}" -o "$dir/one.mvx" > /dev/null 2>&1
  # Loopback and shared memory only (also exported by mpi_common.sh).
  MEGAVOX_TEST_HASH_BITS=$bits mpirun --mca btl self,vader --mca oob_tcp_if_include lo -np "$n" \
    "$megavox" "${args[@]}" -o "$dir/ranks.mvx" > /dev/null \
    2> "$dir/ranks.txt" || fail "$format over $n ranks: $(cat "$dir/ranks.txt")"
  grep -q "seed 1 collided across ranks" "$dir/ranks.txt" ||
    fail "$format over $n ranks: no collision across ranks met: $(cat "$dir/ranks.txt")"
  cmp -s "$dir/one.mvx" "$dir/ranks.mvx" || fail "$format over $n ranks: not the bytes of one process"
done
echo "hash collisions over ranks: found by the keys' owners (svdag over 2 ranks, ssvdag over 8)," \
  "the bytes of one process"

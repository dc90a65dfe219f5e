#!/usr/bin/env bash
# `mpirun -np N megavox points build`: point builds spread over 1, 2, 3 and 5 ranks write the bytes of the
# one-process build: .mvx and 3D Tiles 1.1 and 1.0 (every rank writing its own tiles), from a float PLY with
# colour, a LAS 1.4 with its attribute record and (with ../shared) a LAZ file, on PoCL and lavapipe; --json
# reports every rank; a rank that fails or is killed ends the run with nothing left. Only this machine: shared memory and loopback (never another interface).
# Usage: mpi_points.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"

mpi_test="mpi points"
source "$(dirname "$0")/mpi_common.sh"

# write_cloud PATH N: N points on a bumpy sphere, binary float PLY with colour (fixed seed).
write_cloud() {
  python3 - "$1" "$2" <<'PY'
import array, math, random, sys
path, n = sys.argv[1], int(sys.argv[2])
rnd = random.Random(1)
xyz, rgb = array.array("f"), bytearray()
for _ in range(n):
    t, p = math.acos(2 * rnd.random() - 1), 2 * math.pi * rnd.random()
    r = 1 + 0.12 * math.sin(4 * t) * math.cos(5 * p)
    x, y, z = r * math.sin(t) * math.cos(p), r * math.cos(t), r * math.sin(t) * math.sin(p)
    xyz.extend((x, y, z))
    rgb += bytes((int(110 * (x + 1.2)) & 255, int(110 * (y + 1.2)) & 255, int(110 * (z + 1.2)) & 255))
with open(path, "wb") as out:
    out.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n"
               "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n").encode())
    for i in range(n):
        out.write(xyz[3 * i:3 * i + 3].tobytes() + rgb[3 * i:3 * i + 3])
PY
}

# same_as_one NAME ARGS...: the build in one process, then under mpirun with 1, 2, 3 and 5 ranks: the same bytes.
same_as_one() {
  local name=$1 n
  shift
  "$megavox" "$@" -o "$dir/one_$name" -q > /dev/null || fail "$name: one process failed"
  for n in 1 2 3 5; do
    mpirun -np "$n" "$megavox" "$@" -o "$dir/n_$name" -q > "$dir/out.txt" 2>&1 || fail "$name np $n: $(cat "$dir/out.txt")"
    diff -r "$dir/one_$name" "$dir/n_$name" > /dev/null || fail "$name np $n: not the bytes of one process"
    rm -rf "$dir/n_$name"
  done
}

write_cloud "$dir/cloud.ply" 60000
"$megavox" points convert "$dir/cloud.ply" -o "$dir/cloud.las" > /dev/null
small=(--max-node-points 200)  # a deep hierarchy: levels above the cells dealt to ranks are joined on rank 0
same_as_one ply.mvx points build "$dir/cloud.ply" "${small[@]}"
same_as_one las.mvx points build "$dir/cloud.las" "${small[@]}"
same_as_one tiles points build "$dir/cloud.las" --format 3dtiles "${small[@]}"
same_as_one tiles10 points build "$dir/cloud.ply" --format 3dtiles --tiles-version 1.0 --max-node-points 2000
same_as_one default.mvx points build "$dir/cloud.ply"
same_as_one skip.mvx points build "$dir/cloud.las" --skip-attributes --max-node-points 50
same_as_one vk.mvx --device vk:0 points build "$dir/cloud.ply" "${small[@]}"
same_as_one box.mvx points build "$dir/cloud.las" --bounds -2,-0.5,-2,0.3,2,2 "${small[@]}"  # each slice's points in it
# A binary PLY's ranks read their slices alone, its grid's pass too (the ranks agree on the largest coordinate).
mpirun -np 3 "$megavox" points build "$dir/cloud.ply" "${small[@]}" -o "$dir/slices.mvx" --json > "$dir/slices.json" \
  2> "$dir/out.txt" || fail "PLY slices: $(cat "$dir/out.txt")"
python3 - "$dir/slices.json" "$(stat -c %s "$dir/cloud.ply")" <<'PY' || fail "a PLY rank read the whole file: $(cat "$dir/slices.json")"
import json, sys
r, size = json.load(open(sys.argv[1]))["ranks"], int(sys.argv[2])
assert all(x["bytes_read"] < size / 2 for x in r), r
PY
echo "mpi points: the same bytes over 1, 2, 3 and 5 ranks (PLY, LAS 1.4, --bounds, .mvx, 3D Tiles 1.1 and 1.0, PoCL and lavapipe)"
laz=$(dirname "$0")/../../../shared/data/pointcloud_laz/autzen_trim.laz
if [[ -f $laz ]]; then
  same_as_one laz.mvx points build "$laz" --max-node-points 1000
  same_as_one laz_tiles points build "$laz" --format 3dtiles --max-node-points 5000
  copc=$(dirname "$laz")/1.2-with-color.copc.laz  # a box of a COPC file: each rank decodes the chunks it meets
  same_as_one copc_box.mvx points build "$copc" --bounds 637000,849000,400,638500,851500,600 --max-node-points 50
  echo "mpi points: LAZ to .mvx and 3D Tiles 1.1, the same bytes over 1, 2, 3 and 5 ranks"
else
  echo "mpi points: ../shared is absent, so the LAZ comparison did not run"
fi

# --json: one entry per rank; the slices and the dealt cells each add up to the cloud.
mpirun -np 3 "$megavox" points build "$dir/cloud.las" "${small[@]}" -o "$dir/j.mvx" --json > "$dir/ranks.json" ||
  fail "json: $(cat "$dir/ranks.json")"
python3 - "$dir/ranks.json" "$(stat -c %s "$dir/cloud.las")" <<'PY' || fail "ranks: $(cat "$dir/ranks.json")"
import json, sys
d = json.load(open(sys.argv[1]))  # one object: rank 0's; the other ranks print nothing
r = d["ranks"]
assert len(r) == 3 and all(x["points"] > 0 and x["points_read"] > 0 for x in r), r
assert sum(x["points"] for x in r) == d["points_in"] == sum(x["points_read"] for x in r), r
assert all(x["bytes_exchanged"] > 0 and x["peak_memory_bytes"] > 0 for x in r) and 0 <= d["merge_share"] < 1
# an uncompressed LAS is read by slice: no rank reads the whole file
assert all(0 < x["bytes_read"] < 0.5 * int(sys.argv[2]) for x in r), r
PY

# A tileset's tiles are written by every rank: each its cells' subtrees, rank 0 the levels above and tileset.json.
mpirun -np 3 "$megavox" points build "$dir/cloud.las" --format 3dtiles "${small[@]}" -o "$dir/jt" --json > "$dir/tiles.json" ||
  fail "tiles json: $(cat "$dir/tiles.json")"
python3 - "$dir/tiles.json" "$(ls "$dir/jt/tiles" | wc -l)" <<'PY' || fail "tiles per rank: $(cat "$dir/tiles.json")"
import json, sys
r = json.load(open(sys.argv[1]))["ranks"]
assert all(x["tiles"] > 0 for x in r) and sum(x["tiles"] for x in r) == int(sys.argv[2]), r
PY

# bench points --ranks: one rank and three, timed from outside, the same bytes.
"$megavox" bench points "$dir/cloud.las" --repeats 1 --max-node-points 500 --ranks 3 --json -q > "$dir/bench.json" ||
  fail "bench points --ranks: $(cat "$dir/bench.json")"
python3 - "$dir/bench.json" <<'PY' || fail "bench points --ranks: $(cat "$dir/bench.json")"
import json, sys
r = json.loads(open(sys.argv[1]).readline())["ranks"]
assert r["ranks"] == 3 and r["same_bytes"] and r["speedup"] > 0 and len(r["per_rank"]) == 3, r
PY

# A rank that fails ends the run: rank 1 asks for a device that does not exist.
if mpirun -np 1 "$megavox" points build "$dir/cloud.ply" -o "$dir/failed.mvx" : \
  -np 1 "$megavox" --device no-such-device points build "$dir/cloud.ply" -o "$dir/failed.mvx" > "$dir/fail.txt" 2>&1; then
  fail "a failed rank, yet mpirun succeeded: $(cat "$dir/fail.txt")"
fi
grep -q "rank 1 of 2: error: no device" "$dir/fail.txt" || fail "the failing rank is not named: $(cat "$dir/fail.txt")"
[[ -z $(ls "$dir" | grep failed) ]] || fail "output left after a failed run: $(ls "$dir")"

# An input one rank cannot read: refused on every rank before any work, naming the rank.
if mpirun -np 1 "$megavox" points build "$dir/cloud.ply" -o "$dir/blind.mvx" : \
  -np 1 "$megavox" points build "$dir/nowhere.ply" -o "$dir/blind.mvx" > "$dir/blind.txt" 2>&1; then
  fail "a rank could not read its input, yet mpirun succeeded"
fi
grep -q "rank 1 cannot read it" "$dir/blind.txt" || fail "the blind rank is not named: $(cat "$dir/blind.txt")"
[[ ! -e "$dir/blind.mvx" ]] || fail "output left after an unreadable input"


# Each rank holds its share of the points: a cloud whose share is over the memory budget is refused before any
# work, with nothing left; one whose share fits builds, the bytes of one process, to a .mvx and to 3D Tiles.
if mpirun -np 2 "$megavox" points build "$dir/cloud.las" --memory 1M -o "$dir/mem.mvx" > "$dir/mem.txt" 2>&1; then
  fail "a cloud over each rank's memory built"
fi
grep -q "rank 0 of 2: error: points build over ranks: each rank holds its share" "$dir/mem.txt" ||
  fail "no refusal over the memory budget: $(cat "$dir/mem.txt")"
[[ ! -e "$dir/mem.mvx" ]] || fail "output left after a refused build"
for out in mem.mvx mem_tiles; do
  format=(); [[ $out == mem_tiles ]] && format=(--format 3dtiles)
  mpirun -np 2 "$megavox" points build "$dir/cloud.las" "${format[@]}" --memory 5M "${small[@]}" -o "$dir/$out" \
    --json > "$dir/$out.json" 2> "$dir/mem.txt" || fail "$out within each rank's share was refused: $(cat "$dir/mem.txt")"
  "$megavox" points build "$dir/cloud.las" "${format[@]}" "${small[@]}" -o "$dir/one_$out" -q > /dev/null
  diff -r "$dir/one_$out" "$dir/$out" > /dev/null || fail "$out within the shares: not the bytes of one process"
done
# Rank 0 gets only the points the levels above the dealt cells are made from: for a tileset, fewer bytes than
# for a .mvx, whose points all pass through it on their way into the file.
python3 - "$dir/mem_tiles.json" "$dir/mem.mvx.json" <<'PY' || fail "rank 0 got as much for a tileset as for a .mvx"
import json, sys
tiles, mvx = (json.load(open(p))["ranks"][0]["bytes_exchanged"] for p in sys.argv[1:])
assert tiles < mvx, (tiles, mvx)
PY

# A rank killed mid-build: mpirun ends the others, the status is non-zero within 30 s, and nothing is left.
write_cloud "$dir/big.ply" 600000
expect_killed_rank_ends_run "$dir/killed.mvx" points build "$dir/big.ply" --max-node-points 100
echo "mpi points: ranks reported, bench --ranks; a failed, blind or killed rank ends the run with nothing left"

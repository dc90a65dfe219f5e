#!/usr/bin/env bash
# `mpirun -np N megavox build`: out-of-core builds spread over 1, 2, 3 and 5 ranks write the bytes of the
# one-process build, for every encoding; --json reports every rank; a rank that fails (a device it cannot open)
# ends the run with its rank named, a non-zero status and no output; other verbs are refused under mpirun.
# Only this machine: shared memory and loopback (never another interface).
# Usage: mpi_build.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"

mpi_test="mpi build"
source "$(dirname "$0")/mpi_common.sh"

# A bumpy sphere of 3,200 triangles, with and without vertex colours: enough cubes (4^3 at 128^3 in cubes of
# 32^3) for every rank.
write_sphere_ply "$dir/sphere.ply" 40
write_sphere_ply "$dir/coloured.ply" 40 rgb
args=(build "$dir/sphere.ply" --resolution 128 --cube 32 -q)

for format in svdag ssvdag ussvdag svo; do
  "$megavox" "${args[@]}" --format "$format" -o "$dir/one.mvx" > /dev/null
  for n in 1 2 3 5; do
    mpirun -np "$n" "$megavox" "${args[@]}" --format "$format" -o "$dir/n$n.mvx" > "$dir/out.txt" 2>&1 ||
      fail "np $n $format: $(cat "$dir/out.txt")"
    cmp -s "$dir/one.mvx" "$dir/n$n.mvx" || fail "np $n $format: not the bytes of one process"
  done
done
# Colours travel with their cube's part.
# 8 cubes over 9 ranks: some ranks make no cube, yet take part in the merge's reductions.
for format in svdag ssvdag; do
  few=(build "$dir/sphere.ply" --resolution 128 --cube 64 -q --format "$format")
  "$megavox" "${few[@]}" -o "$dir/few_one.mvx" > /dev/null
  mpirun -np 9 "$megavox" "${few[@]}" -o "$dir/few9.mvx" --json > "$dir/few.json" 2> "$dir/out.txt" ||
    fail "np 9 $format: $(cat "$dir/out.txt")"
  cmp -s "$dir/few_one.mvx" "$dir/few9.mvx" || fail "np 9 $format: not the bytes of one process"
  python3 -c 'import json, sys; assert 0 in [r["cubes"] for r in json.load(open(sys.argv[1]))["ranks"]]' "$dir/few.json" ||
    fail "np 9: every rank had a cube: $(cat "$dir/few.json")"
done
coloured=(build "$dir/coloured.ply" --resolution 128 --cube 32 -q --format ssvdag)
"$megavox" "${coloured[@]}" -o "$dir/c_one.mvx" > /dev/null
"$megavox" info "$dir/c_one.mvx" | grep -q "colours:" || fail "the coloured sphere built without colours"
for n in 2 3; do
  mpirun -np "$n" "$megavox" "${coloured[@]}" -o "$dir/c$n.mvx" > "$dir/out.txt" 2>&1 ||
    fail "coloured np $n: $(cat "$dir/out.txt")"
  cmp -s "$dir/c_one.mvx" "$dir/c$n.mvx" || fail "coloured np $n: not the bytes of one process"
done
echo "mpi build: the same bytes over 1, 2, 3 and 5 ranks (svdag, ssvdag, ussvdag, svo; coloured over 2 and 3; 9 ranks for 8 cubes)"

# binary_ply IN OUT [QUAD]: the ascii sphere as binary little-endian, its faces uchar + int lists (with QUAD, the
# last two triangles as one quad face, which leaves its faces unreadable by offset).
binary_ply() {
  python3 - "$@" <<'PY'
import struct, sys
lines = open(sys.argv[1]).read().split("\n")
end = lines.index("end_header")
head, body = lines[:end], lines[end + 1:]
nv = int(next(l for l in head if l.startswith("element vertex")).split()[2])
nf = int(next(l for l in head if l.startswith("element face")).split()[2])
rgb = any(l.endswith(" red") for l in head)
faces = [list(map(int, l.split()[1:])) for l in body[nv:nv + nf]]
if len(sys.argv) > 3:
    a, b = faces[-2], faces[-1]
    faces = faces[:-2] + [[a[0], a[1], b[2], a[2]]]
out = open(sys.argv[2], "wb")
out.write("\n".join(l.replace("format ascii 1.0", "format binary_little_endian 1.0").replace(f"element face {nf}", f"element face {len(faces)}") for l in head).encode() + b"\nend_header\n")
for l in body[:nv]:
    v = l.split()
    out.write(struct.pack("<3f", *map(float, v[:3])) + (bytes(map(int, v[3:6])) if rgb else b""))
for f in faces:
    out.write(struct.pack("<B", len(f)) + struct.pack(f"<{len(f)}i", *f))
PY
}
# Binary triangles: each rank reads the vertices and its share of the faces by offset, and the cubes' triangles
# go to their owners; a quad face leaves every rank reading the whole mesh. The same bytes either way.
binary_ply "$dir/sphere.ply" "$dir/sphere_bin.ply"
binary_ply "$dir/coloured.ply" "$dir/coloured_bin.ply"
binary_ply "$dir/sphere.ply" "$dir/quad_bin.ply" quad
# ushort colours: 16-bit in the last vertex alone (each rank reads a share of the vertices, and they must agree
# to keep the high byte), and 16-bit storage of 8-bit values.
ushort_ply() {
  python3 - "$@" <<'PY'
import struct, sys
src, out, wide = sys.argv[1], sys.argv[2], sys.argv[3] == "wide"
data = open(src, "rb").read()
head, body = data.split(b"end_header\n", 1)
lines = head.decode().split("\n")
nv = int(next(l for l in lines if l.startswith("element vertex")).split()[2])
lines = [l.replace("property uchar", "property ushort") if (l.split() or [""])[-1] in ("red", "green", "blue") else l for l in lines]
verts = []
for i in range(nv):
    x, y, z, r, g, b = struct.unpack_from("<3f3B", body, 15 * i)
    if wide and i == nv - 1:
        r = 4000
    verts.append(struct.pack("<3f3H", x, y, z, r, g, b))
open(out, "wb").write("\n".join(lines).encode() + b"end_header\n" + b"".join(verts) + body[15 * nv:])
PY
}
ushort_ply "$dir/coloured_bin.ply" "$dir/wide_bin.ply" wide
ushort_ply "$dir/coloured_bin.ply" "$dir/narrow_bin.ply" narrow
for input in sphere_bin coloured_bin quad_bin wide_bin narrow_bin; do
  shared=(build "$dir/$input.ply" --resolution 128 --cube 32 -q --format ssvdag)
  "$megavox" "${shared[@]}" -o "$dir/${input}_one.mvx" > /dev/null
  for n in 2 3 5; do
    mpirun -np "$n" "$megavox" "${shared[@]}" -o "$dir/${input}_$n.mvx" --json > "$dir/shares.json" 2> "$dir/out.txt" ||
      fail "$input np $n: $(cat "$dir/out.txt")"
    cmp -s "$dir/${input}_one.mvx" "$dir/${input}_$n.mvx" || fail "$input np $n: not the bytes of one process"
    python3 - "$dir/shares.json" "$(stat -c %s "$dir/$input.ply")" "$input" <<'PY' || fail "$input np $n: $(cat "$dir/shares.json")"
import json, sys
r, size, shared = json.load(open(sys.argv[1]))["ranks"], int(sys.argv[2]), sys.argv[3] != "quad_bin"
assert all((x["bytes_read"] < size) == shared for x in r), r  # a share of the faces, or the whole file
PY
  done
done
echo "mpi build: binary triangles and vertices read in shares (8- and 16-bit colours too), a quad face read whole: the same bytes"

# The other device kind, and --json: one entry per rank, each with cubes and voxels of its own.
mpirun -np 3 "$megavox" --device vk:0 "${args[@]}" --format ssvdag -o "$dir/vk.mvx" --json > "$dir/ranks.json" ||
  fail "vk:0: $(cat "$dir/ranks.json")"
"$megavox" --device vk:0 "${args[@]}" --format ssvdag -o "$dir/vk_one.mvx" > /dev/null
cmp -s "$dir/vk.mvx" "$dir/vk_one.mvx" || fail "vk:0 np 3: not the bytes of one process"
python3 - "$dir/ranks.json" <<'PY' || fail "ranks: $(cat "$dir/ranks.json")"
import json, sys
d = json.load(open(sys.argv[1]))  # one object: rank 0's; the other ranks print nothing
r = d["ranks"]
assert len(r) == 3 and all(x["cubes"] > 0 and x["voxels"] > 0 for x in r), r
assert sum(x["voxels"] for x in r) == d["voxels"], (r, d["voxels"])
assert all(x["bytes_exchanged"] > 0 and x["peak_memory_bytes"] > 0 for x in r) and 0 <= d["merge_share"] < 1
PY

# A rank that fails ends the run: rank 1 asks for a device that does not exist.
rm -f "$dir/failed.mvx"
if mpirun -np 1 "$megavox" "${args[@]}" -o "$dir/failed.mvx" : -np 1 "$megavox" --device no-such-device "${args[@]}" \
  -o "$dir/failed.mvx" > "$dir/fail.txt" 2>&1; then
  fail "a failed rank, yet mpirun succeeded: $(cat "$dir/fail.txt")"
fi
grep -q "rank 1 of 2: error: no device" "$dir/fail.txt" || fail "the failing rank is not named: $(cat "$dir/fail.txt")"
[[ -z $(ls "$dir" | grep failed) ]] || fail "output left after a failed run: $(ls "$dir")"

# A rank killed mid-build: mpirun ends the others, the status is non-zero within 30 s, and nothing is left.
expect_killed_rank_ends_run "$dir/killed.mvx" build "$dir/sphere.ply" --resolution 1024 --cube 64

# An input one rank cannot read: refused on every rank before any work, naming the rank.
if mpirun -np 1 "$megavox" "${args[@]}" -o "$dir/blind.mvx" : -np 1 "$megavox" build "$dir/nowhere.ply" \
  --resolution 128 --cube 32 -q -o "$dir/blind.mvx" > "$dir/blind.txt" 2>&1; then
  fail "a rank could not read its input, yet mpirun succeeded"
fi
grep -q "rank 1 cannot read it" "$dir/blind.txt" || fail "the blind rank is not named: $(cat "$dir/blind.txt")"
[[ ! -e "$dir/blind.mvx" ]] || fail "output left after an unreadable input"

# Verbs other than build would run once per rank: refused.
if mpirun -np 2 "$megavox" info "$dir/one.mvx" > "$dir/info.txt" 2>&1; then fail "info ran under mpirun"; fi
grep -q "under mpirun only \`megavox build\` and" "$dir/info.txt" || fail "no refusal: $(cat "$dir/info.txt")"
# bench build --ranks: one rank and three, timed from outside, the same bytes.
"$megavox" bench build "$dir/sphere.ply" --resolution 128 --cube 32 --no-peer --ranks 3 --json > "$dir/bench.json" ||
  fail "bench build --ranks: $(cat "$dir/bench.json")"
python3 - "$dir/bench.json" <<'PY' || fail "bench build --ranks: $(cat "$dir/bench.json")"
import json, sys
r = json.load(open(sys.argv[1]))["ranks"]
assert r["ranks"] == 3 and r["same_bytes"] and r["speedup"] > 0 and len(r["per_rank"]) == 3, r
PY
echo "mpi build: ranks reported, a failed or killed rank ends the run with nothing left, other verbs refused, bench --ranks"

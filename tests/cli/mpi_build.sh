#!/usr/bin/env bash
# `mpirun -np N megavox build`: out-of-core builds spread over 1, 2, 3 and 5 ranks write the bytes of the
# one-process build, for every encoding; --json reports every rank; a rank that fails (a device it cannot open)
# ends the run with its rank named, a non-zero status and no output; other verbs are refused under mpirun.
# Only this machine: shared memory and loopback (never another interface).
# Usage: mpi_build.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"

if ! command -v mpirun >/dev/null; then echo "mpi build: no mpirun (scripts/setup.sh installs openmpi-bin)"; exit 0; fi
if "$megavox" --version | grep -q "MPI: not built in"; then echo "mpi build: megavox built without MPI"; exit 0; fi
export OMPI_MCA_btl=self,vader OMPI_MCA_oob_tcp_if_include=lo OMPI_MCA_btl_tcp_if_include=lo
export OMPI_MCA_rmaps_base_oversubscribe=1
[[ $(id -u) -eq 0 ]] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# A bumpy sphere of 3,200 triangles: enough cubes (4^3 at 128^3 in cubes of 32^3) for every rank.
python3 - "$dir/sphere.ply" <<'PY'
import math, sys
rows, cols = 40, 40
v = []
for i in range(rows + 1):
    t = math.pi * i / rows
    for j in range(cols):
        p = 2 * math.pi * j / cols
        r = 1 + 0.15 * math.sin(5 * t) * math.cos(3 * p)
        v.append((r * math.sin(t) * math.cos(p), r * math.cos(t), r * math.sin(t) * math.sin(p)))
f = []
for i in range(rows):
    for j in range(cols):
        a, b = i * cols + j, i * cols + (j + 1) % cols
        c, d = a + cols, b + cols
        f += [(a, c, b), (b, c, d)]
with open(sys.argv[1], "w") as out:
    out.write(f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
              f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    out.writelines(f"{x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in v)
    out.writelines(f"3 {a} {b} {c}\n" for a, b, c in f)
PY
args=(build "$dir/sphere.ply" --resolution 128 --cube 32 -q)

for format in svdag ssvdag svo; do
  "$megavox" "${args[@]}" --format "$format" -o "$dir/one.mvx" > /dev/null
  for n in 1 2 3 5; do
    mpirun -np "$n" "$megavox" "${args[@]}" --format "$format" -o "$dir/n$n.mvx" > "$dir/out.txt" 2>&1 ||
      fail "np $n $format: $(cat "$dir/out.txt")"
    cmp -s "$dir/one.mvx" "$dir/n$n.mvx" || fail "np $n $format: not the bytes of one process"
  done
done
echo "mpi build: the same bytes over 1, 2, 3 and 5 ranks (svdag, ssvdag, svo)"

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

# Verbs other than build would run once per rank: refused.
if mpirun -np 2 "$megavox" info "$dir/one.mvx" > "$dir/info.txt" 2>&1; then fail "info ran under mpirun"; fi
grep -q "only \`megavox build\` runs" "$dir/info.txt" || fail "no refusal: $(cat "$dir/info.txt")"
echo "mpi build: ranks reported, a failed rank ends the run, other verbs refused"

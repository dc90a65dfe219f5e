#!/usr/bin/env bash
# What `megavox build` says on stderr before a wait: the kernel compile notice on a cold kernel cache (only on a
# terminal, which `script` gives it; not on a warm cache, not with --quiet, not into a file), and the plan line,
# which `build --json` prints on stderr too while stdout holds exactly one JSON object with a "plan" in it.
# Usage: build_notices.sh MEGAVOX
set -euo pipefail
megavox=$(realpath "$1")
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
notice="megavox: compiling kernels for"

# On a terminal: `script` runs the command on a pseudo-terminal and copies what it shows.
on_terminal() { script -qec "$1" /dev/null; }

if "$megavox" devices | grep -qiE "pocl|Portable Computing Language"; then
  build="MEGAVOX_DEVICE=pocl '$megavox' build '$dir/tetra.ply' --resolution 64 -o '$dir/t.mvx'"
  shown=$(on_terminal "MEGAVOX_KERNEL_CACHE='$dir/cold' $build")
  grep -q "$notice .*(first use; cached for later runs)" <<<"$shown" || fail "no compile notice on a cold cache: $shown"
  grep -q "kernels   compiling 2: [a-z_]*/[a-z_]*\.cl" <<<"$shown" || fail "no progress line over the kernels: $shown"
  shown=$(on_terminal "MEGAVOX_KERNEL_CACHE='$dir/cold' $build")
  if grep -q "$notice" <<<"$shown"; then fail "a compile notice on a warm cache: $shown"; fi
  shown=$(on_terminal "MEGAVOX_KERNEL_CACHE='$dir/quiet' $build --quiet")
  if grep -q "$notice" <<<"$shown"; then fail "a compile notice with --quiet: $shown"; fi
  MEGAVOX_DEVICE=pocl MEGAVOX_KERNEL_CACHE="$dir/file" "$megavox" build "$dir/tetra.ply" --resolution 64 \
    -o "$dir/t.mvx" >/dev/null 2>"$dir/err"
  if grep -q "$notice" "$dir/err"; then fail "a compile notice into a file: $(cat "$dir/err")"; fi
  [[ -n "$(ls "$dir/file")" ]] || fail "the kernel cache was not written"
else
  echo "no PoCL device: the OpenCL compile notice is not checked"
fi
# Vulkan on lavapipe: the driver compiles each pipeline (its own cache keeps them); the first one megavox has no
# record of is announced.
if "$megavox" devices | grep -qi llvmpipe; then
  build="MEGAVOX_DEVICE=llvmpipe MEGAVOX_KERNEL_CACHE='$dir/vk' '$megavox' build '$dir/tetra.ply' --resolution 64 -o '$dir/t.mvx'"
  shown=$(on_terminal "$build")
  grep -q "$notice llvmpipe" <<<"$shown" || fail "no compile notice on lavapipe: $shown"
  shown=$(on_terminal "$build")
  if grep -q "$notice" <<<"$shown"; then fail "a compile notice on lavapipe's second run: $shown"; fi
fi

"$megavox" build "$dir/tetra.ply" --resolution 256 --json -o "$dir/t.mvx" >"$dir/out" 2>"$dir/err"
grep -q "^megavox: plan: 256^3 grid, voxel .*, origin .*; in core$" "$dir/err" || fail "no plan line: $(cat "$dir/err")"
grep -q "^megavox: estimated [0-9KMG]* voxels, output " "$dir/err" || fail "no estimate line: $(cat "$dir/err")"
python3 - "$dir/out" <<'PY' || fail "stdout is not one JSON object with the plan: $(cat "$dir/out")"
import json, sys
text = open(sys.argv[1]).read()
obj, end = json.JSONDecoder().raw_decode(text)
assert text[end:].strip() == "", "more than one object"
p = obj["plan"]
assert p["resolution"] == 256 and not p["out_of_core"] and p["triangles"] == 4, p
for k in ("voxel_size", "origin", "estimated_voxels", "estimated_output_bytes", "estimated_host_bytes",
          "estimated_device_bytes", "cube", "cubes", "warnings"):
    assert k in p, k
# The tetrahedron's surface is known: the estimate is within a factor of two of the voxels built.
assert 0.5 < p["estimated_voxels"] / obj["voxels"] < 2, (p["estimated_voxels"], obj["voxels"])
# The stages: reading the file apart from the voxelization, as for every input.
assert {"read", "voxelize"} <= set(obj["seconds"]), obj["seconds"]
PY
"$megavox" build "$dir/tetra.ply" --resolution 4K --cube 1024 --quiet -o "$dir/t.mvx" >/dev/null 2>"$dir/err"
[[ ! -s "$dir/err" ]] || fail "--quiet printed on stderr: $(cat "$dir/err")"
"$megavox" build "$dir/tetra.ply" --resolution 4K --cube 1024 -o "$dir/t.mvx" >/dev/null 2>"$dir/err"
grep -q "out of core in cubes of 1024^3 (64 cubes, about [0-9]* meeting the surface)" "$dir/err" ||
  fail "no out-of-core plan: $(cat "$dir/err")"
echo "build notices: ok"

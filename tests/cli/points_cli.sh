#!/usr/bin/env bash
# `megavox points` as a user runs it: build (table, --json, 3dtiles), info, render, --during-build, and bad
# input ending in one clear error line, a non-zero exit and no output file. No shared data needed: the clouds
# are written here.
set -euo pipefail
mv=$1
source "$(dirname "$0")/common.sh"

# A small ascii PLY cloud: a 20 x 20 x 20 lattice with colours.
{
  echo ply; echo "format ascii 1.0"; echo "element vertex 8000"
  echo "property float x"; echo "property float y"; echo "property float z"
  echo "property uchar red"; echo "property uchar green"; echo "property uchar blue"; echo end_header
  for x in $(seq 0 19); do for y in $(seq 0 19); do for z in $(seq 0 19); do
    echo "$x.5 $y.25 $z $((x * 12)) $((y * 12)) $((z * 12))"
  done; done; done
} > "$dir/lattice.ply"

"$mv" points build "$dir/lattice.ply" -o "$dir/l.mvx" --max-node-points 500 > "$dir/table.txt"
grep -q "points in 8000, kept 8000, dropped 0" "$dir/table.txt" || fail "summary: $(cat "$dir/table.txt")"
"$mv" points build "$dir/lattice.ply" -o "$dir/l2.mvx" --max-node-points 500 --json > "$dir/b.json"
for key in points_in points_kept points_dropped nodes_per_level depth seconds points_per_second; do
  grep -q "\"$key\"" "$dir/b.json" || fail "points build --json lacks $key"
done
grep -q '"read"' "$dir/b.json" && grep -q '"sort"' "$dir/b.json" && grep -q '"write"' "$dir/b.json" || fail "seconds"
cmp -s "$dir/l.mvx" "$dir/l2.mvx" || fail "two builds of the same cloud differ"
# --profile: the parallelism profile inside the JSON, and on stderr for a person; --kernel-shape gpu: same bytes.
"$mv" --profile --kernel-shape gpu points build "$dir/lattice.ply" -o "$dir/l3.mvx" --max-node-points 500 --json \
  > "$dir/p.json"
grep -q '"parallelism"' "$dir/p.json" && grep -q '"narrow_seconds"' "$dir/p.json" || fail "no profile in the JSON"
cmp -s "$dir/l.mvx" "$dir/l3.mvx" || fail "--kernel-shape gpu changed the bytes"
"$mv" --profile points build "$dir/lattice.ply" -o "$dir/l4.mvx" --max-node-points 500 2> "$dir/p.txt" >/dev/null
grep -q '^profile points build: wall .* device .* dispatches under' "$dir/p.txt" || fail "profile: $(cat "$dir/p.txt")"
bad=$("$mv" --kernel-shape wide devices 2>&1) && fail "--kernel-shape wide was taken"
grep -q -- '--kernel-shape: wide not in {auto,gpu,cpu}' <<<"$bad" || fail "a bad --kernel-shape is not named: $bad"
shaped=$("$mv" --kernel-shape gpu devices --json)
grep -q '"kernel_shape": "gpu"' <<<"$shaped" || fail "devices --json shows no shape: $shaped"
"$mv" points info "$dir/l.mvx" | grep -q "8000 points" || fail "points info"
"$mv" points info "$dir/l.mvx" --json | grep -q '"points_kept": 8000' || fail "points info --json"
"$mv" points render "$dir/l.mvx" -o "$dir/l.png" --width 200 --height 150 > /dev/null
[[ -s "$dir/l.png" ]] || fail "no picture"
# The camera and size options of `render`: 1920x1080 by default, --up as a vector or an axis, --eye/--target in
# the cloud's units (the lattice spans 0.5..19.5 x 0.25..19.25 x 0..19).
"$mv" points render "$dir/l.mvx" -o "$dir/default.png" | grep -q "(1920x1080)" || fail "points render's default size"
"$mv" points render "$dir/l.mvx" -o "$dir/up_axis.png" --width 96 --height 64 --view front --up z -q
"$mv" points render "$dir/l.mvx" -o "$dir/up_vec.png" --width 96 --height 64 --view front --up 0,0,1 -q
cmp -s "$dir/up_axis.png" "$dir/up_vec.png" || fail "--up z differs from --up 0,0,1"
cmp -s "$dir/up_vec.png" "$dir/l.png" && fail "--up 0,0,1 made the default picture"
"$mv" points render "$dir/l.mvx" -o "$dir/eye.png" --width 96 --height 64 --eye 10,10,60 --target 10,10,9.5 \
  --up 0,1,0 --json > "$dir/eye.json"
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert j["pixels_covered"] > 96 * 64 / 10, j' \
  "$dir/eye.json" || fail "--eye/--target: $(cat "$dir/eye.json")"
"$mv" points render "$dir/l.mvx" -o "$dir/front.png" --width 96 --height 64 --view front --fov 40 -q
"$mv" points render "$dir/l.mvx" -o "$dir/far.png" --width 96 --height 64 --eye 10,9.75,200 --target 10,9.75,9.5 -q
cmp -s "$dir/front.png" "$dir/far.png" && fail "--eye was ignored"
"$mv" points build "$dir/lattice.ply" --format 3dtiles -o "$dir/tiles" > /dev/null
[[ -s "$dir/tiles/tileset.json" ]] || fail "no tileset"
"$mv" points render "$dir/lattice.ply" --during-build --frames 3 -o "$dir/frames" --max-node-points 500 \
  --width 120 --height 90 --json > "$dir/frames.jsonl"
[[ $(wc -l < "$dir/frames.jsonl") == 3 && -s "$dir/frames/frame_0002.png" ]] || fail "frames: $(cat "$dir/frames.jsonl")"
grep -q "\"front_nodes\":" "$dir/frames.jsonl" || fail "frames without front_nodes: $(cat "$dir/frames.jsonl")"
"$mv" points render "$dir/lattice.ply" --during-build --frames 2 -o "$dir/frames_text" --max-node-points 500 \
  --width 60 --height 45 > "$dir/frames.txt"
[[ $(grep -c '^frame [01]: .* nodes, .* drawn, .* points -> ' "$dir/frames.txt") == 2 ]] ||
  fail "frames without --json: $(cat "$dir/frames.txt")"
"$mv" points build "$dir/lattice.ply" -o "$dir/ooc.mvx" --max-node-points 500 --memory 300K > /dev/null
cmp -s "$dir/l.mvx" "$dir/ooc.mvx" || fail "out of core differs from in core"

# Bad input: one error line, exit 1, nothing written.
expect_error() {  # expect_error WORDS ARGS...
  local words=$1; shift
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  grep -q "$words" "$dir/err.txt" || fail "'$*' said: $(cat "$dir/err.txt")"
}
printf 'LASF' > "$dir/short.las"
expect_error "truncated\|too short\|header" points build "$dir/short.las" -o "$dir/bad.mvx"
head -c 300 "$dir/lattice.ply" > "$dir/cut.ply"
expect_error "truncated\|complete" points build "$dir/cut.ply" -o "$dir/bad.mvx"
# A LAS 1.2 header whose point format has the LAZ compression bit (0x80) set, and nothing else right.
{ printf 'LASF'; head -c 20 /dev/zero; printf '\001\002'; head -c 68 /dev/zero; printf '\343\000\343\000\000\000'
  head -c 4 /dev/zero; printf '\203\042\000'; head -c 120 /dev/zero; } > "$dir/scan.laz"
expect_error "LAZ\|scale factor" points build "$dir/scan.laz" -o "$dir/bad.mvx"
expect_error "no such\|cannot open" points build "$dir/none.ply" -o "$dir/bad.mvx"
printf 'ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n' \
  > "$dir/empty.ply"
expect_error "empty.ply: the cloud has no points" points build "$dir/empty.ply" -o "$dir/bad.mvx"
expect_error "up wants X,Y,Z" points render "$dir/l.mvx" -o "$dir/bad.png" --up w
expect_error "target needs --eye" points render "$dir/l.mvx" -o "$dir/bad.png" --target 1,2,3
expect_error "depth" points build "$dir/lattice.ply" -o "$dir/bad.mvx" --depth 30
expect_error "format" points build "$dir/lattice.ply" -o "$dir/bad.mvx" --format copc
expect_error "point cloud" info "$dir/l.mvx"
expect_error "holds voxels\|not a .mvx\|bad magic" points info "$dir/lattice.ply"
[[ ! -e "$dir/bad.mvx" && ! -e "$dir/bad.png" ]] || fail "an output was left after an error"
echo "points CLI: ok"

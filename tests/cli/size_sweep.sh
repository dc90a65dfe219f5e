#!/usr/bin/env bash
# Absurd values of every size option of every command, as a new user might type them: each run must end in
# success or one clear error (megavox's or CLI11's), never "internal error" (exit 2), a signal or a hang, and
# a failed run leaves no output behind. Budgets too small to hold anything must name what is needed.
# SWEEP_LOG=FILE: append each case, its exit status and its message there (to read them over).
set -euo pipefail
mv=$1
source "$(dirname "$0")/common.sh"

write_tetra_ply "$dir/t.ply"
{
  echo ply; echo "format ascii 1.0"; echo "element vertex 512"
  echo "property float x"; echo "property float y"; echo "property float z"; echo end_header
  for x in $(seq 0 7); do for y in $(seq 0 7); do for z in $(seq 0 7); do echo "$x $y $z"; done; done; done
} > "$dir/c.ply"
"$mv" build "$dir/t.ply" --resolution 16 -o "$dir/t.mvx" > /dev/null
"$mv" points build "$dir/c.ply" -o "$dir/c.mvx" > /dev/null

cases=0
# run_case ARGS...: any outcome but an internal error, a signal, a timeout or a leftover output.
run_case() {
  cases=$((cases + 1))
  local rc=0
  timeout 60 "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt" || rc=$?
  if ((rc == 124)); then fail "timed out: $*"; fi
  if ((rc == 2 || rc > 128)); then fail "exit $rc for: $* ($(head -c 300 "$dir/err.txt"))"; fi
  if grep -q "internal error" "$dir/err.txt"; then fail "internal error for: $* ($(cat "$dir/err.txt"))"; fi
  if ((rc != 0)); then
    [[ -s "$dir/err.txt" ]] || fail "exit $rc without a message: $*"
    for f in "$dir"/o.*; do [[ ! -e "$f" ]] || fail "'$*' failed and left $f"; done
  fi
  rm -rf "$dir"/o.*
  [[ -z ${SWEEP_LOG:-} ]] || echo "$rc $* :: $(head -c 400 "$dir/err.txt")" >> "$SWEEP_LOG"
  return 0
}
# expect_error WORDS ARGS...: fails with a message matching WORDS (grep -E).
expect_error() {
  local words=$1; shift
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  grep -Eq "$words" "$dir/err.txt" || fail "'$*' said: $(cat "$dir/err.txt")"
  grep -q "internal error" "$dir/err.txt" && fail "internal error for: $*"
  for f in "$dir"/o.*; do [[ ! -e "$f" ]] || fail "'$*' failed and left $f"; done
  return 0
}

sizes=(0 1 3 1K 64K 1M 2M 4G 1T 99999999999T -1 abc 1.5 18446744073709551616)
counts=(0 1 -1 4294967295 4294967296 99999999999999999999 abc)
reals=(0 -1 1e308 -1e308 nan inf 1e-300)

for v in "${sizes[@]}"; do
  # a valid resolution of 4K and up is a real (long) job on a tetrahedron filling its grid
  [[ $v == 64K ]] || run_case build "$dir/t.ply" --resolution "$v" -o "$dir/o.mvx"
  run_case build "$dir/t.ply" --resolution 64 --memory "$v" -o "$dir/o.mvx"
  run_case --device-memory "$v" build "$dir/t.ply" --resolution 16 -o "$dir/o.mvx"
  run_case points build "$dir/c.ply" --memory "$v" -o "$dir/o.mvx"
  run_case bench sort --n "$v" --repeats 1
done
for v in "${counts[@]}"; do
  run_case build "$dir/t.ply" --resolution 64 --cube "$v" -o "$dir/o.mvx"
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width "$v" --height 8
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width 8 --height "$v"
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width 8 --height 8 --ao-samples "$v"
  run_case points build "$dir/c.ply" --depth "$v" -o "$dir/o.mvx"
  run_case points build "$dir/c.ply" --max-node-points "$v" -o "$dir/o.mvx"
  run_case points render "$dir/c.mvx" -o "$dir/o.png" --width "$v" --height 8
  run_case points render "$dir/c.mvx" -o "$dir/o.png" --width 8 --height "$v"
  run_case points render "$dir/c.mvx" -o "$dir/o.png" --width 8 --height 8 --point-size "$v"
  run_case points render "$dir/c.ply" --during-build -o "$dir/o.frames" --width 8 --height 8 --frames "$v"
done
for v in "${reals[@]}"; do
  run_case build "$dir/t.ply" --resolution 16 --bounds "0,0,0,$v" -o "$dir/o.mvx"
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width 8 --height 8 --fov "$v"
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width 8 --height 8 --lod-pixels "$v"
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width 8 --height 8 --ao-radius "$v"
  run_case render "$dir/t.mvx" -o "$dir/o.png" --width 8 --height 8 --eye "$v,1,1"
  run_case points render "$dir/c.mvx" -o "$dir/o.png" --width 8 --height 8 --fov "$v"
  run_case points render "$dir/c.mvx" -o "$dir/o.png" --width 8 --height 8 --lod-pixels "$v"
done

# What the budgets need, said before anything is allocated, in units that show them.
expect_error "1048576.*cubes.*GiB.*--cube" build "$dir/t.ply" --resolution 1M -o "$dir/o.mvx"
expect_error "need 2.\.. KiB of host memory, over the 768 B" build "$dir/t.ply" --resolution 64 --memory 1K -o "$dir/o.mvx"
expect_error "page" --device-memory 1K build "$dir/t.ply" --resolution 16 -o "$dir/o.mvx"
expect_error "device memory: .* needs .*budget 64.0 KiB.* \(raise --device-memory\)$" --device-memory 64K build "$dir/t.ply" --resolution 256 -o "$dir/o.mvx"
expect_error "device memory: .* needs .*budget 64.0 KiB" --device-memory 64K points build "$dir/c.ply" -o "$dir/o.mvx"
# a file larger than the host budget: the mesh, the cloud
expect_error "the mesh needs about [0-9]+ B of host memory, over the host memory budget 100 B \(raise --memory\)" build "$dir/t.ply" --memory 100 -o "$dir/o.mvx"
expect_error "512 points need about 1.\.. KiB of host memory .*over the host memory budget 1.0 KiB \(raise --memory\)" points build "$dir/c.ply" --memory 1K -o "$dir/o.mvx"
echo "size sweep: $cases cases, ok"

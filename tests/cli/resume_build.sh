#!/usr/bin/env bash
# `megavox build --resume`: a build in cubes killed mid-way goes on from the cubes it kept, and writes the bytes
# of a build that was never stopped; a damaged kept cube is made again; cubes kept by a build with other options
# are not reused; the folder goes once the output is written; a build in one piece refuses --resume. Under
# mpirun (when megavox has MPI), the ranks resume from the same folder.
# Usage: resume_build.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"

write_sphere_ply "$dir/ball.ply" 60 rgb
args=(build "$dir/ball.ply" --resolution 512 --cube 64 --format ssvdag -q)
"$megavox" "${args[@]}" -o "$dir/ref.mvx" > /dev/null
out=$dir/out.mvx
kept=$out.cubes

# stop_midway: a --resume build killed once it kept at least 4 cubes
stop_midway() {
  "$megavox" "${args[@]}" --resume -o "$out" > /dev/null 2>&1 &
  local run=$!
  for _ in $(seq 400); do
    (($(ls "$kept" 2>/dev/null | grep -c '\.part$' || true) >= 4)) && break
    sleep 0.025
  done
  kill -9 "$run" 2>/dev/null || true
  wait "$run" 2>/dev/null || true
  n=$(ls "$kept" 2>/dev/null | grep -c '\.part$' || true)
  ((n >= 4)) || fail "the killed build kept $n cubes (it should have kept at least 4 before the kill)"
  [[ ! -e "$out" ]] || fail "a killed build left its output"
}

stop_midway
resumed=$("$megavox" "${args[@]}" --resume -o "$out" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['cubes_resumed'])")
((resumed >= 4 && resumed <= n)) || fail "resumed $resumed cubes of the $n kept"
cmp -s "$dir/ref.mvx" "$out" || fail "a resumed build is not the bytes of an unstopped one"
[[ ! -e "$kept" ]] || fail "the kept cubes are left after the output was written"
echo "resume: $resumed kept cubes reused, the same bytes, the folder removed"

# A damaged kept cube is made again.
rm -f "$out"
stop_midway
victim=$(ls "$kept"/*.part | head -1)
printf '\x55' | dd of="$victim" bs=1 seek=100 conv=notrunc status=none
resumed=$("$megavox" "${args[@]}" --resume -o "$out" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['cubes_resumed'])")
((resumed == n - 1)) || fail "with one of $n kept cubes damaged, $resumed were reused"
cmp -s "$dir/ref.mvx" "$out" || fail "a resume over a damaged cube is not the bytes of an unstopped build"

# Cubes kept by a build with other options are not reused.
rm -f "$out"
stop_midway
"$megavox" build "$dir/ball.ply" --resolution 512 --cube 64 --format svdag -q -o "$dir/ref_svdag.mvx" > /dev/null
resumed=$("$megavox" build "$dir/ball.ply" --resolution 512 --cube 64 --format svdag -q --resume -o "$out" --json |
  python3 -c "import json,sys; print(json.load(sys.stdin)['cubes_resumed'])")
((resumed == 0)) || fail "cubes of an ssvdag build were reused by an svdag build"
cmp -s "$dir/ref_svdag.mvx" "$out" || fail "the svdag build over another build's cubes is not its own bytes"
echo "resume: a damaged cube made again; another build's cubes not reused"

# In one piece: refused before any work.
if "$megavox" build "$dir/ball.ply" --resolution 64 --resume -o "$dir/small.mvx" > "$dir/err.txt" 2>&1; then
  fail "--resume on a build in one piece"
fi
grep -q "resume keeps the cubes of a build in cubes" "$dir/err.txt" || fail "no clear refusal: $(cat "$dir/err.txt")"

# Under mpirun, the ranks take the kept cubes of a one-process run.
if command -v mpirun > /dev/null && ! "$megavox" --version | grep -q "MPI: not built in"; then
  export OMPI_MCA_btl=self,vader OMPI_MCA_oob_tcp_if_include=lo OMPI_MCA_btl_tcp_if_include=lo
  export OMPI_MCA_rmaps_base_oversubscribe=1
  [[ $(id -u) -eq 0 ]] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  rm -f "$out"
  stop_midway
  mpirun -np 2 "$megavox" "${args[@]}" --resume -o "$out" > /dev/null 2>&1 || fail "mpirun --resume failed"
  cmp -s "$dir/ref.mvx" "$out" || fail "mpirun --resume: not the bytes of an unstopped build"
  [[ ! -e "$kept" ]] || fail "mpirun --resume left the kept cubes"
  echo "resume: two ranks went on from a one-process run's cubes"
fi

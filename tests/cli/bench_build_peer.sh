#!/usr/bin/env bash
# `megavox bench build` with stand-ins for voxcom: the peer gets the mesh and log2 of the resolution, its STATS
# lines land in the JSON, a missing peer is one line, a mismatched rule is not run, a failing peer is one line and megavox's figures still come.
# Usage: bench_build_peer.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
# The stand-in checks its arguments as voxcom takes them and prints the stats patch's lines.
cat >"$dir/peer.sh" <<'SH'
#!/usr/bin/env bash
[[ $# -eq 8 && $2 == 6 && $3 == --out && $5 == --svdag && $7 == --ussvdag && -f $1 ]] || { echo "bad arguments: $*"; exit 3; }
echo "[info] STATS svdag level 6: svo_nodes=1 dag_nodes=1"
echo "[info] STATS svdag total: voxels=1234 svo_nodes=56 dag_nodes=40"
echo "[info] STATS ssvdag total: voxels=1234 svo_nodes=56 dag_nodes=30"
SH
printf '#!/bin/sh\necho "out of memory"\nexit 1\n' >"$dir/failing.sh"
chmod +x "$dir/peer.sh" "$dir/failing.sh"

run() { "$megavox" bench build "$dir/tetra.ply" --resolution 64 "$@"; }

json=$(run --voxelize thin --grid-origin min --format ssvdag --peer "$dir/peer.sh" --repeats 2 --json)
for field in '"peer_status": "ran"' '"counts_from": "ssvdag"' '"voxels": 1234' '"dag_nodes": 30' '"wall_ratio"' \
             '"rss_ratio"' '"max_rss_bytes"' '"peak_rss_bytes"' '"voxels_per_s"' '"triangles": 4' '"read_ratio"'; do
  grep -qF "$field" <<<"$json" || fail "no $field in: $json"
done

text=$(run --voxelize thin --grid-origin min --peer "$dir/absent")
[[ $(grep -c 'peer' <<<"$text") == 1 ]] || fail "a missing peer is not one line: $text"
grep -q 'voxcom not built.*build.sh' <<<"$text" || fail "no build hint: $text"

grep -q 'peer: not run: .*thin' <<<"$(run --peer "$dir/peer.sh")" || fail "the conservative rule ran the peer"

out=$(run --voxelize thin --grid-origin min --peer "$dir/failing.sh" 2>&1) || fail "a failing peer stopped the benchmark: $out"
grep -q 'peer: .*failed (exit status 1)' <<<"$out" && grep -q 'out of memory' <<<"$out" || fail "unclear peer failure: $out"
grep -q 'voxels/s' <<<"$out" || fail "no megavox figures beside a failing peer: $out"
echo "bench build with stand-in peers: ok"

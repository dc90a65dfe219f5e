#!/usr/bin/env bash
# `megavox bench cache` on a paged tetrahedron built here: every figure present, the frames converged and
# byte-identical to the resident render, a cache share and an address-layer ratio measured.
# Usage: bench_cache_smoke.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
"$megavox" build "$dir/tetra.ply" --resolution 512 --format svo -o "$dir/t.mvx" >/dev/null
json=$("$megavox" bench cache "$dir/t.mvx" --cache-memory 16M --frames 2 --width 64 --height 48 --ao-samples 2 --json)
python3 - "$json" <<'PY' || fail "bad figures: $json"
import json, sys
j = json.loads(sys.argv[1])
assert j["benchmark"] == "cache" and len(j["frames"]) == 2
assert j["identical_frames"] == 2
assert 0 <= j["cache_share"] < 1 and j["address_layer_cost"] > 0 and 0 <= j["hit_rate"] <= 1
for f in j["frames"]:
    assert f["converged"] and f["passes"] >= 1 and f["resident_seconds"] > 0 and f["paged_seconds"] > 0
PY
echo "bench cache smoke: ok"

#!/usr/bin/env bash
# `megavox bench trace` on a tetrahedron built here, resident and through a small page cache: every figure
# present, steps per ray counted, both runs agreeing on the hits, the paged renders converged.
# Usage: bench_trace_smoke.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
"$megavox" build "$dir/tetra.ply" --resolution 512 --format svdag -o "$dir/t.mvx" >/dev/null
"$megavox" build "$dir/tetra.ply" --resolution 512 --format ssvdag -o "$dir/s.mvx" >/dev/null
args=(--width 96 --height 64 --repeats 2 --json)
resident=$("$megavox" bench trace "$dir/t.mvx" "$dir/s.mvx" "${args[@]}")
paged=$("$megavox" bench trace "$dir/t.mvx" "$dir/s.mvx" "${args[@]}" --cache-memory 1M)
python3 - "$resident" "$paged" <<'PY' || fail "bad figures: $resident / $paged"
import json, sys
r, p = json.loads(sys.argv[1]), json.loads(sys.argv[2])
assert r["benchmark"] == "trace" and r["cache_memory"] == 0 and p["cache_memory"] == 1 << 20
for j, paged in ((r, False), (p, True)):
    assert [e["format"] for e in j["encodings"]] == ["svdag", "ssvdag"]
    for e in j["encodings"]:
        assert e["paged"] == paged and e["converged"]
        assert e["hits"] > 0 and e["primary_mrays"] > 0 and e["shadow_mrays"] > 0 and e["ao_mrays"] > 0
        s = e["steps_per_ray"]
        assert 0 < s["primary"] <= s["primary_hit"] and s["shadow"] > 0 and s["ao"] > 0
        # the renders' own steps: with the beam pre-pass, fewer than the whole walk's
        assert 0 < s["primary_rendered"] < s["primary"] and 0 < s["primary_hit_rendered"] <= s["primary_hit"]
        assert e["primary_mrays_no_beam"] > 0
assert [e["hits"] for e in r["encodings"]] == [e["hits"] for e in p["encodings"]]
assert r["encodings"][0]["steps_per_ray"] == r["encodings"][1]["steps_per_ray"]  # one walk for every encoding
assert r["encodings"][0]["steps_per_ray"]["primary_rendered"] < r["encodings"][0]["steps_per_ray"]["primary"]
PY
echo "bench trace smoke: ok"

#!/usr/bin/env bash
# `megavox bench attributes` on a coloured lattice cloud written here: every figure present, colour bits per voxel
# never above raw storage, quantized builds with a ΔE, and the coloured render differing from the grey one.
# Usage: bench_attributes_smoke.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_lattice_ply "$dir/lattice.ply" 16 16
json=$("$megavox" bench attributes "$dir/lattice.ply" --resolution 32 --bits 24,12 --repeats 1 --width 64 --height 48 --json)
python3 - "$json" <<'PY' || fail "bad figures: $json"
import json, sys
c = json.loads(sys.argv[1])["clouds"][0]
assert c["points"] == 4096 and c["voxels"] == 4096 and c["entries"] > 4096, c
assert [b["colour_bits"] for b in c["coloured"]] == [24, 12], c
for b in c["coloured"]:
    assert 0 < b["colour_bits_per_voxel"] <= b["raw_bits_per_voxel"] * 1.02, b
    assert 0 < b["compression_rate"] <= 1.01 and b["stage_ratio"] > 0 and b["peak_rss_bytes"] > 0, b
assert "quantize" in c["coloured"][1] and c["coloured"][1]["quantize"]["colours_out"] <= 4096, c
assert c["hits"] > 0 and c["pixels_changed"] > c["hits"] // 2 and c["render_ratio"] > 0, c
PY
echo "bench attributes smoke: ok"

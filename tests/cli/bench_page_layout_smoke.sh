#!/usr/bin/env bash
# `megavox bench page-layout` on a tetrahedron built here: one row per order and page size with every figure,
# the same page count for both orders, padding under 5 %, and an encoding it cannot page refused with a message.
# Usage: bench_page_layout_smoke.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
"$megavox" build "$dir/tetra.ply" --resolution 256 --format svdag -o "$dir/t.mvx" >/dev/null
json=$("$megavox" bench page-layout "$dir/t.mvx" --page-words 256,1024 --paths 500 --json)
rows=$(grep -c '"order"' <<<"$json")
[[ $rows == 4 ]] || fail "not 4 layouts (2 orders x 2 page sizes): $json"
for f in pages size_ratio crossing_pointers pages_per_path max_pages_per_path layout_seconds; do
  [[ $(grep -c "\"$f\"" <<<"$json") == 4 ]] || fail "no $f in every layout: $json"
done
python3 - "$json" <<'PY' || fail "bad figures: $json"
import json, sys
j = json.loads(sys.argv[1])
rows = j["layouts"]
for pw in (256, 1024):  # at most 8 padding words a page: under 3.2 %
    lv, st = [r for r in rows if r["page_words"] == pw]
    assert lv["order"] == "level" and st["order"] == "subtree"
    assert lv["pages"] == st["pages"] or abs(lv["pages"] - st["pages"]) <= 1
    assert 1.0 <= lv["size_ratio"] < 1.05 and 1.0 <= st["size_ratio"] < 1.05
    assert 1.0 <= st["pages_per_path"] <= j["levels"]
PY
"$megavox" build "$dir/tetra.ply" --resolution 256 --format ssvdag -o "$dir/s.mvx" >/dev/null
if err=$("$megavox" bench page-layout "$dir/s.mvx" 2>&1); then fail "an ssvdag was paged: $err"; fi
grep -q "ssvdag is paged in level order only" <<<"$err" || fail "no clear message: $err"
echo "bench page-layout smoke: ok"

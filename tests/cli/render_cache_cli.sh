#!/usr/bin/env bash
# `megavox render --cache-memory` and `--path` on a tetrahedron built here (a paged .mvx: the plain octree, 16 KiB pages):
# a cache a third of the file renders the same PNG bytes as the resident render, a flight writes its
# frames and one JSON line each with the cache's figures, a one-page cache warns and still writes a picture,
# and what cannot work fails with a clear message and no output: an ssvdag (not paged), a cache smaller
# than a page, a cache over --device-memory, a malformed flight.
# Usage: render_cache_cli.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
"$megavox" build "$dir/tetra.ply" --resolution 512 --format svo -o "$dir/t.mvx" >/dev/null
info=$("$megavox" info "$dir/t.mvx" --json)
read -r pages page_words < <(python3 -c 'import json,sys; j=json.loads(sys.argv[1]); p=j["paging"]; print(p["pages"], p["page_words"])' "$info")
(( pages >= 16 )) || fail "expected at least 16 pages: $info"
cache=$(( pages * page_words * 4 / 3 ))
view=(--eye 0.45,0.45,0.9 --target 0.2,0.2,0.2 --fov 25 --width 160 --height 120)
"$megavox" render "$dir/t.mvx" -o "$dir/resident.png" "${view[@]}" --quiet
json=$("$megavox" render "$dir/t.mvx" -o "$dir/paged.png" "${view[@]}" --cache-memory "$cache" --json)
cmp "$dir/resident.png" "$dir/paged.png" || fail "the paged render differs from the resident one: $json"
python3 - "$json" <<'PY' || fail "bad cache figures: $json"
import json, sys
c = json.loads(sys.argv[1])["cache"]
assert c["converged"] and c["passes"] >= 2 and c["pages_loaded"] >= 1 and c["coarse_pixels"] == 0
for k in ("pages_requested", "pages_evicted", "hit_rate", "bytes_uploaded", "cache_seconds", "io_seconds"):
    assert k in c, k
PY
# a flight (whole views: a cache that holds the file): one JSON line per frame, frames in the folder
cat >"$dir/flight.json" <<'JSON'
{"fov": 30, "frames": [{"eye": [0.5, 0.5, 1.2], "target": [0.2, 0.2, 0.2], "up": [0, 1, 0]},
                       {"eye": [1.2, 0.5, 0.5], "target": [0.2, 0.2, 0.2], "up": [0, 1, 0]},
                       {"eye": [0.5, 1.2, 0.5], "target": [0.2, 0.2, 0.2], "up": [0, 0, 1]}]}
JSON
lines=$("$megavox" render "$dir/t.mvx" --path "$dir/flight.json" -o "$dir/frames" --cache-memory 16M \
  --width 64 --height 48 --json)
[[ $(wc -l <<<"$lines") == 3 ]] || fail "not one JSON line per frame: $lines"
for i in 0 1 2; do [[ -s $dir/frames/frame_000$i.png ]] || fail "no frame $i"; done
python3 - "$lines" <<'PY' || fail "bad frame lines: $lines"
import json, sys
for i, line in enumerate(sys.argv[1].splitlines()):
    j = json.loads(line)
    assert j["frame"] == i and "cache" in j and j["cache"]["converged"]
PY
# one page: the root's level of detail, a warning, a picture all the same
err=$("$megavox" render "$dir/t.mvx" -o "$dir/one.png" "${view[@]}" --lod-pixels 0 --cache-memory $(( page_words * 4 )) 2>&1 >/dev/null)
grep -q "warning: .*coarser level" <<<"$err" || fail "no warning for a one-page cache: $err"
[[ -s $dir/one.png ]] || fail "no picture from a one-page cache"
# refusals
expect_error() {  # expect_error PATTERN ARGS...: fails with a message matching PATTERN, writes no output
  local pattern=$1
  shift
  if out=$("$megavox" "$@" 2>&1); then fail "accepted: $*"; fi
  grep -q "$pattern" <<<"$out" || fail "unclear message for $*: $out"
  [[ ! -e $dir/bad.png && ! -e $dir/badframes ]] || fail "output left behind by $*"
}
"$megavox" build "$dir/tetra.ply" --resolution 64 --format ssvdag -o "$dir/s.mvx" >/dev/null
expect_error "resident" render "$dir/s.mvx" -o "$dir/bad.png" --cache-memory 16M
expect_error "holds no page" render "$dir/t.mvx" -o "$dir/bad.png" --cache-memory 1K
expect_error "device memory\|budget" --device-memory 4M render "$dir/t.mvx" -o "$dir/bad.png" --cache-memory 64M
echo '{"frames": [{"eye": [1, 1, 1]}]}' >"$dir/bad.json"
expect_error "frame 0: no \"target\"" render "$dir/t.mvx" --path "$dir/bad.json" -o "$dir/badframes" --cache-memory "$cache"
echo "render --cache-memory / --path: ok"

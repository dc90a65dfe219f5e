#!/usr/bin/env bash
# `megavox render --cache-memory` and `--path` on a tetrahedron built here (a paged .mvx: the plain octree, 16 KiB pages):
# a cache a third of the file renders the same PNG bytes as the resident render, a flight writes its
# frames and one JSON line each with the cache's figures, the same octree paged in level order (--page-order)
# renders the same PNG, a coloured cloud's colours stream with its pages (the same colour PNG), a one-page cache warns and still writes a picture,
# an ssvdag (paged level by level) renders the resident PNG through a quarter of its pages, and what cannot work
# fails with a clear message and no output: a cache smaller
# than a page, a cache over --device-memory, a row of pixels that does not fit beside the cache (a frame that
# does not fit renders in bands, the same PNG), a malformed flight.
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
# --page-order level: the same octree with its levels one after another, pointers counting from their level's
# start; the same PNG through the same share of its pages
"$megavox" build "$dir/tetra.ply" --resolution 512 --format svo --page-order level -o "$dir/tl.mvx" >/dev/null
linfo=$("$megavox" info "$dir/tl.mvx" --json)
lpages=$(python3 -c 'import json,sys; p=json.loads(sys.argv[1])["paging"]; assert p["node_order"] == "level"; print(p["pages"])' "$linfo")
"$megavox" render "$dir/tl.mvx" -o "$dir/level.png" "${view[@]}" --cache-memory $(( lpages * page_words * 4 / 3 )) --quiet
cmp "$dir/resident.png" "$dir/level.png" || fail "the level-order paged render differs from the resident one"
# a coloured cloud: its colours stream with the pages (info says so), the same colour picture through a third
write_lattice_ply "$dir/lattice.ply" 24 2
"$megavox" build "$dir/lattice.ply" --resolution 64 --format svo --page-words 64 -o "$dir/c.mvx" >/dev/null
cinfo=$("$megavox" info "$dir/c.mvx" --json)
cpages=$(python3 -c 'import json,sys; p=json.loads(sys.argv[1])["paging"]; assert p["size_plane"]; print(p["pages"])' "$cinfo")
"$megavox" info "$dir/c.mvx" | grep -q "colours stream with the pages" || fail "info does not say the colours stream"
cview=(--view iso --width 96 --height 72 --shading colour --quiet)
"$megavox" render "$dir/c.mvx" -o "$dir/c_resident.png" "${cview[@]}"
"$megavox" render "$dir/c.mvx" -o "$dir/c_paged.png" "${cview[@]}" --cache-memory $(( (cpages / 3 + 16) * 512 ))
cmp "$dir/c_resident.png" "$dir/c_paged.png" || fail "the streamed colour render differs from the resident one"
# the ssvdag, paged in its own layout: a cache a quarter of its pages renders the resident PNG too (a bumpy
# sphere: a tetrahedron's ssvdag is one page, its symmetry folds it)
python3 - "$dir/bumpy.ply" <<'PY'
import math, random, sys
random.seed(5)
nu, nv = 96, 48
verts, faces = [], []
for j in range(nv + 1):
    th = math.pi * j / nv
    for i in range(nu):
        ph, r = 2 * math.pi * i / nu, 0.4 * (1 + 0.08 * random.uniform(-1, 1))
        verts.append((0.5 + r * math.sin(th) * math.cos(ph), 0.5 + r * math.cos(th), 0.5 + r * math.sin(th) * math.sin(ph)))
for j in range(nv):
    for i in range(nu):
        a, b = j * nu + i, j * nu + (i + 1) % nu
        faces += [(a, a + nu, b), (b, a + nu, b + nu)]
with open(sys.argv[1], "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(verts), len(faces)))
    f.writelines("%f %f %f\n" % v for v in verts)
    f.writelines("3 %d %d %d\n" % t for t in faces)
PY
"$megavox" build "$dir/bumpy.ply" --resolution 512 --format ssvdag -o "$dir/s.mvx" >/dev/null
sinfo=$("$megavox" info "$dir/s.mvx" --json)
spages=$(python3 -c 'import json,sys; p=json.loads(sys.argv[1])["paging"]; assert p["node_order"] == "level"; print(p["pages"])' "$sinfo")
(( spages >= 32 )) || fail "expected at least 32 ssvdag pages: $sinfo"
"$megavox" render "$dir/s.mvx" -o "$dir/s_resident.png" "${view[@]}" --quiet
"$megavox" render "$dir/s.mvx" -o "$dir/s_paged.png" "${view[@]}" --cache-memory $(( (spages + 3) / 4 * page_words * 4 )) --quiet
cmp "$dir/s_resident.png" "$dir/s_paged.png" || fail "the paged ssvdag render differs from the resident one"
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
# one warning line, blaming only what the user gave: --cache-passes when given, never when not
[[ $(wc -l <<<"$err") == 1 ]] || fail "more than one warning line: $err"
! grep -q -- "--cache-passes" <<<"$err" || fail "the warning blames --cache-passes, not given: $err"
err=$("$megavox" render "$dir/t.mvx" --path "$dir/flight.json" -o "$dir/coarse_frames" --width 64 --height 48 \
  --lod-pixels 0 --cache-memory $(( page_words * 4 )) 2>&1 >/dev/null)
[[ $(wc -l <<<"$err") == 1 ]] &&
  grep -q "warning: 3 of 3 frames (the first .*frame_0000.png) show a coarser" <<<"$err" ||
  fail "not one warning line for the flight: $err"
! grep -q -- "--cache-passes" <<<"$err" || fail "the flight's warning blames --cache-passes, not given: $err"
err=$("$megavox" render "$dir/t.mvx" -o "$dir/one_pass.png" "${view[@]}" --cache-memory "$cache" --cache-passes 1 \
  2>&1 >/dev/null)
grep -q "warning: .*--cache-passes ended the frame first" <<<"$err" || fail "--cache-passes 1 not named: $err"
[[ -s $dir/one.png ]] || fail "no picture from a one-page cache"
# refusals
expect_error() {  # expect_error PATTERN ARGS...: fails with a message matching PATTERN, writes no output
  local pattern=$1
  shift
  if out=$("$megavox" "$@" 2>&1); then fail "accepted: $*"; fi
  grep -q "$pattern" <<<"$out" || fail "unclear message for $*: $out"
  [[ ! -e $dir/bad.png && ! -e $dir/badframes ]] || fail "output left behind by $*"
}
expect_error "holds no page" render "$dir/t.mvx" -o "$dir/bad.png" --cache-memory 1K
expect_error "device memory.*page cache slots" --device-memory 256K render "$dir/t.mvx" -o "$dir/bad.png" --cache-memory 1M
expect_error "one row of 16384 pixels needs" --device-memory 2M render "$dir/t.mvx" -o "$dir/bad.png" --cache-memory 512K \
  --width 16384 --height 4
# a frame whose buffers do not fit beside the cache renders in bands of rows: the resident PNG all the same
"$megavox" --device-memory 4M render "$dir/t.mvx" -o "$dir/banded.png" "${view[@]/160/640}" --cache-memory 1M --quiet
"$megavox" render "$dir/t.mvx" -o "$dir/whole.png" "${view[@]/160/640}" --quiet
cmp "$dir/whole.png" "$dir/banded.png" || fail "the banded frame differs from the whole one"
echo '{"frames": [{"eye": [1, 1, 1]}]}' >"$dir/bad.json"
expect_error "frame 0: no \"target\"" render "$dir/t.mvx" --path "$dir/bad.json" -o "$dir/badframes" --cache-memory "$cache"
echo "render --cache-memory / --path: ok"

#!/usr/bin/env bash
# `megavox info` on the paged .mvx (version 3) a build writes: the paging it prints (text and --json), every
# page checked (a flipped byte inside a page is named), and an ssvdag file paged in level order.
# Usage: info_paged.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"
"$megavox" build "$dir/tetra.ply" --resolution 256 --format svdag -o "$dir/t.mvx" >/dev/null
text=$("$megavox" info "$dir/t.mvx")
grep -q "paged: 4096-word pages (16 KiB), [0-9]* pages, subtree order" <<<"$text" || fail "no paging line: $text"
grep -q "not paged" <<<"$text" && fail "a paged file also said to be not paged: $text"
json=$("$megavox" info "$dir/t.mvx" --json)
python3 - "$json" <<'PY' || fail "bad paging in --json: $json"
import json, sys
j = json.loads(sys.argv[1])
p = j["paging"]
assert p["page_words"] == 4096 and p["page_bytes"] == 16384 and p["node_order"] == "subtree", p
assert p["pages"] == (p["paged_words"] + 4095) // 4096 and 1.0 <= p["size_ratio"] < 1.05, p
PY
# A flip in the first page of the nodes (the fourth 4 KiB block: header, counts, levels, nodes).
cp "$dir/t.mvx" "$dir/bad.mvx"
printf '\x5a' | dd of="$dir/bad.mvx" bs=1 seek=$((3 * 4096 + 10)) conv=notrunc status=none
if err=$("$megavox" info "$dir/bad.mvx" 2>&1); then fail "a damaged page passed: $err"; fi
grep -q "checksum mismatch in page 0" <<<"$err" || fail "no clear message: $err"
"$megavox" build "$dir/tetra.ply" --resolution 256 --format ssvdag -o "$dir/s.mvx" >/dev/null
"$megavox" info "$dir/s.mvx" | grep -q "paged: .* level order" || fail "ssvdag not said to be paged in level order"
"$megavox" info "$dir/s.mvx" --json | python3 -c '
import json, sys
p = json.load(sys.stdin)["paging"]
assert p["node_order"] == "level" and 1.0 <= p["size_ratio"] < 1.05, p' || fail "bad ssvdag --json paging"
echo "info paged: ok"

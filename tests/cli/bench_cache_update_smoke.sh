#!/usr/bin/env bash
# `megavox bench cache-update` on a small cache: every figure in the JSON, pages loaded and uploaded, about the same
# hit rate for the device cache and the CPU LRU (both exact LRUs over the same views), and a bad view refused.
# Usage: bench_cache_update_smoke.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
json=$("$megavox" bench cache-update --slots 64 --pages 1000 --page-words 16 --passes 20 --view 40 --drift 7 --json)
python3 - "$json" <<'PY' || fail "bad figures: $json"
import json, sys
j = json.loads(sys.argv[1])
for f in ("device_manage_ms", "device_produce_ms", "cpu_lru_ms", "ratio", "device_hit_rate", "cpu_hit_rate",
          "loads", "evictions", "bytes_uploaded"):
    assert f in j, f
assert j["loads"] > 0 and j["bytes_uploaded"] == j["loads"] * 16 * 4
assert 0 < j["device_hit_rate"] < 1 and abs(j["device_hit_rate"] - j["cpu_hit_rate"]) <= 0.02
PY
if err=$("$megavox" bench cache-update --pages 10 --view 11 2>&1); then fail "a view over the pages ran: $err"; fi
grep -q "view <= pages" <<<"$err" || fail "no clear message: $err"
echo "bench cache-update smoke: ok"

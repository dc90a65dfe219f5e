#!/usr/bin/env bash
# The load test (tests/serve/serve_load.cpp) against a server started here, with the server's resident memory
# sampled throughout: it must stay under a bound (no growth with the requests served).
# Usage: serve_load.sh MEGAVOX SERVE_LOAD SOURCE_DIR
set -euo pipefail
mv=$1
load=$2
src=$3
source "$src/tests/cli/common.sh"
source "$src/tests/serve/serve_common.sh"
start_server "$dir/data" --max-jobs 2 --max-queue 8 --device-memory 512M
rss() { awk '/^VmRSS/ {print $2}' /proc/$pid/status; }
peak=0
( while kill -0 $pid 2>/dev/null; do rss; sleep 0.25; done ) > "$dir/rss.txt" 2>/dev/null &
sampler=$!
"$load" "$url" "$token" 32 50 110 || fail "the load test failed"
kill $sampler 2>/dev/null || true
peak=$(sort -n "$dir/rss.txt" | tail -1)
echo "server peak resident memory: $((peak / 1024)) MiB"
((peak < 1536 * 1024)) || fail "server memory reached $((peak / 1024)) MiB"

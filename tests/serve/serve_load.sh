#!/usr/bin/env bash
# The load test (tests/serve/serve_load.cpp) against a server started here, with the server's resident memory
# sampled throughout: it must stay under a bound (no growth with the requests served). Its ray queries go to a
# small build and to a scene 8x the query context's device share.
# Usage: serve_load.sh MEGAVOX SERVE_LOAD SOURCE_DIR
set -euo pipefail
mv=$1
load=$2
src=$3
source "$src/tests/cli/common.sh"
source "$src/tests/serve/serve_common.sh"
# a scene 8x the query share (57M over two workers and the queries: 19 MB each), streamed through the cache
mkdir -p "$dir/data"
write_tetra_ply "$dir/tetra.ply"
"$mv" build "$dir/tetra.ply" --resolution 4096 --format svo -o "$dir/data/big.mvx" --quiet > /dev/null
big_bytes=$(stat -c %s "$dir/data/big.mvx")
((big_bytes >= 8 * 19 * 1000 * 1000)) || fail "the big scene is only $big_bytes bytes"
start_server "$dir/data" --max-jobs 2 --max-queue 8 --device-memory 57M
rss() { awk '/^VmRSS/ {print $2}' /proc/$pid/status; }
peak=0
( while kill -0 $pid 2>/dev/null; do rss; sleep 0.25; done ) > "$dir/rss.txt" 2>/dev/null &
sampler=$!
"$load" "$url" "$token" 32 50 110 big.mvx || fail "the load test failed"
kill $sampler 2>/dev/null || true
peak=$(sort -n "$dir/rss.txt" | tail -1)
echo "server peak resident memory: $((peak / 1024)) MiB"
((peak < 1536 * 1024)) || fail "server memory reached $((peak / 1024)) MiB"

#!/usr/bin/env bash
# `megavox bench points` on a cloud it samples from a small mesh written here (no shared data): every figure is
# in the JSON, every sampled point is kept, the kept sample times as an input file too, and the table names the
# PotreeConverter figure as published, not measured.
# Usage: bench_points_smoke.sh MEGAVOX
set -euo pipefail
megavox=$1
source "$(dirname "$0")/common.sh"
write_tetra_ply "$dir/tetra.ply"

# A field's number in one compact JSON line ("name":value).
field() { grep -o "\"$1\":[-0-9.e+]*" <<<"$2" | head -1 | cut -d: -f2; }

json=$("$megavox" bench points --sample-mesh "$dir/tetra.ply" --sample-points 200K --keep-sample "$dir/s.ply" -q --json)
[[ $(wc -l <<<"$json") == 1 ]] || fail "not one JSON line per cloud: $json"
for f in points_per_second read_floor_seconds read_floor_points_per_second plain_read_seconds ratio_to_read_floor \
         points points_kept nodes depth stored_points peak_rss_bytes vs_potree_quoted total_with_write_seconds \
         read_store_seconds; do
  [[ -n $(field "$f" "$json") ]] || fail "no number $f in: $json"
done
for f in '"seconds":{"build":' '"read":' '"sort":' '"write":' '"sample":{' '"potree_status":"PotreeConverter: not run'; do
  grep -qF "$f" <<<"$json" || fail "no $f in: $json"
done
for f in '"parallelism":{' '"device_seconds":' '"host_seconds":' '"narrow_seconds":' '"io_seconds":' \
         '"kernels":[{' '"launches":' '"work_items":'; do
  grep -qF "$f" <<<"$json" || fail "no $f in the parallelism profile: $json"
done
[[ $(field points "$json") == 204800 ]] || fail "200K is not 204800 points: $json"
[[ $(field points_kept "$json") == "$(field points "$json")" ]] || fail "points_kept != points: $json"
[[ $(field read_floor_points "$json") == 204800 ]] || fail "the read floor did not decode every point: $json"
[[ $(stat -c %s "$dir/s.ply") == $(field bytes "$json") ]] || fail "the sample's size is not its report's"
head -c 300 "$dir/s.ply" | grep -q 'property uchar red' || fail "the sample carries no colour"

# The same sample again: the same bytes (a fixed seed).
"$megavox" bench points --sample-mesh "$dir/tetra.ply" --sample-points 200K --keep-sample "$dir/t.ply" -q --json >/dev/null
cmp -s "$dir/s.ply" "$dir/t.ply" || fail "two samples with the same seed differ"

text=$("$megavox" bench points "$dir/s.ply" --repeats 2 -q)
grep -q 'read floor .*best of 2:' <<<"$text" || fail "no read floor of 2 repeats: $text"
grep -q "vs PotreeConverter 2's published .*(not measured here)" <<<"$text" &&
  grep -q 'PotreeConverter: not run' <<<"$text" || fail "the Potree figure is not labelled as published: $text"
grep -q 'parallelism (best build, read to write): device .* narrow dispatches' <<<"$text" ||
  fail "no parallelism line: $text"
! grep -qi "issue" <<<"$("$megavox" bench points --help)" || fail "the help speaks of an issue"
grep -q '^| s.ply | 204800 |' <<<"$text" || fail "no summary row: $text"
echo "bench points smoke: ok"

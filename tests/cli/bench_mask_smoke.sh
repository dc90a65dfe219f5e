#!/usr/bin/env bash
# `megavox bench mask` on a two-image database written here (a red disc on a green checker, no shared data):
# every cut equals Boost BK's, every figure is in the JSON, and OpenCV's cv::grabCut is either measured beside
# ours or named as not built in (the test build has no baselines).
# Usage: bench_mask_smoke.sh MEGAVOX
set -euo pipefail
mv=$1
source "$(dirname "$0")/common.sh"

# write_disc NAME W H: images/NAME.ppm and masks/NAME.pgm (255 in the disc, 0 outside)
write_disc() {
  local w=$2 h=$3 x y
  { printf 'P6\n%d %d\n255\n' "$w" "$h"
    for ((y = 0; y < h; y++)); do for ((x = 0; x < w; x++)); do
      if (( (2 * x - w) * (2 * x - w) + (2 * y - h) * (2 * y - h) < h * h / 2 )); then printf '\310\060\050'
      elif (( (x / 6 + y / 6) % 2 )); then printf '\050\226\074'; else printf '\064\156\100'; fi
    done; done; } > "$dir/db/images/$1.ppm"
  { printf 'P5\n%d %d\n255\n' "$w" "$h"
    for ((y = 0; y < h; y++)); do for ((x = 0; x < w; x++)); do
      if (( (2 * x - w) * (2 * x - w) + (2 * y - h) * (2 * y - h) < h * h / 2 )); then printf '\377'; else printf '\000'; fi
    done; done; } > "$dir/db/masks/$1.pgm"
}
mkdir -p "$dir/db/images" "$dir/db/masks"
write_disc a 48 36
write_disc b 40 40

json=$("$mv" bench mask --data "$dir/db" --cut-images 1 --images 2 --iterations 2 --json)
for key in speedup_vs_bk grabcut_mean_error grabcut_mean_post_error grabcut_seconds_per_image grabcut_mpx_per_second \
           megavox_cuts_per_second bk_cuts_per_second missing_baselines cut_parallelism grabcut_parallelism \
           device_seconds host_seconds narrow_seconds work_items; do
  grep -q "\"$key\"" <<<"$json" || fail "bench mask --json lacks $key: $json"
done
grep -q '"all_cuts_equal_bk": true' <<<"$json" || fail "a cut differs from BK's: $json"
[[ $(grep -c '"same_cut_as_bk": true' <<<"$json") == 4 ]] || fail "not 4 cuts (2 sizes, 4- and 8-connected): $json"
[[ $(grep -c '"post_error"' <<<"$json") == 2 ]] || fail "not 2 GrabCut images: $json"

grep -q '"min_cut_solver": "\(regions\|push-relabel\)"' <<<"$json" || fail "no solver named: $json"
pr=$("$mv" bench mask --data "$dir/db" --cut-images 1 --images 1 --iterations 2 --min-cut-solver push-relabel --json)
grep -q '"min_cut_solver": "push-relabel"' <<<"$pr" && grep -q '"all_cuts_equal_bk": true' <<<"$pr" ||
  fail "--min-cut-solver push-relabel: $pr"

text=$("$mv" bench mask --data "$dir/db" --cut-images 0 --images 2 --iterations 2)
grep -q '^a  .* 48x36 ' <<<"$text" && grep -q '^b  .* 40x40 ' <<<"$text" || fail "no per-image rows: $text"
if grep -q '"opencv_mean_error"' <<<"$json"; then
  [[ $(grep -c '"opencv_error"' <<<"$json") == 2 ]] || fail "OpenCV did not run on both images: $json"
  grep -q '^OpenCV cv::grabCut, same boxes and iterations: mean error' <<<"$text" || fail "no OpenCV line: $text"
else
  grep -q 'OpenCV cv::grabCut: not built in (needs libopencv-imgproc-dev' <<<"$json" ||
    fail "OpenCV neither measured nor named as missing: $json"
  grep -q '^OpenCV cv::grabCut: not built in' <<<"$text" || fail "the text does not say OpenCV is missing: $text"
fi

# Images far below ~1 MP: the BK speedup, defined over ~1 MP 8-connected cuts, is not measured, and says so.
grep -q '"speedup_vs_bk": null' <<<"$json" || fail "a speedup from no ~1 MP cut: $json"
grep -q '^speedup_vs_bk: not measured (no ~1 MP 8-connected cut' <<<"$text" || fail "no 'not measured' line: $text"

# A folder that is not a database: one clear error, non-zero exit (with --json, as one JSON object on stdout).
if "$mv" bench mask --data "$dir/nowhere" --json > "$dir/out.txt" 2> "$dir/err.txt"; then fail "a missing database passed"; fi
grep -q '"error":.*no images in' "$dir/out.txt" && grep -q '"code":"MV_ERROR_' "$dir/out.txt" ||
  fail "unclear error: $(cat "$dir/out.txt" "$dir/err.txt")"
if "$mv" bench mask --data "$dir/nowhere" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "a missing database passed"; fi
grep -q "no images in" "$dir/err.txt" || fail "unclear error: $(cat "$dir/err.txt")"
echo "bench mask smoke: ok"

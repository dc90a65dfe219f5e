#!/usr/bin/env bash
# `megavox mask` as a user runs it: train a model, apply it, a box, a seed map and a batch list, --json and
# --overlay; bad input ending in one clear error line, a non-zero exit and no mask. The images are written
# here (a red disc on a green checker), no shared data needed.
set -euo pipefail
mv=$1
source "$(dirname "$0")/common.sh"

# write_disc DIR NAME W H: NAME.ppm (the picture) and NAME.pgm (its truth: 255 in the disc, 0 outside)
write_disc() {
  local w=$3 h=$4 x y
  { printf 'P6\n%d %d\n255\n' "$w" "$h"
    for ((y = 0; y < h; y++)); do for ((x = 0; x < w; x++)); do
      if (( (2 * x - w) * (2 * x - w) + (2 * y - h) * (2 * y - h) < h * h / 2 )); then printf '\310\060\050'
      elif (( (x / 6 + y / 6) % 2 )); then printf '\050\226\074'; else printf '\064\156\100'; fi
    done; done; } > "$1/$2.ppm"
  { printf 'P5\n%d %d\n255\n' "$w" "$h"
    for ((y = 0; y < h; y++)); do for ((x = 0; x < w; x++)); do
      if (( (2 * x - w) * (2 * x - w) + (2 * y - h) * (2 * y - h) < h * h / 2 )); then printf '\377'; else printf '\000'; fi
    done; done; } > "$1/$2.pgm"
}
mkdir -p "$dir/photos" "$dir/truth"
write_disc "$dir/photos" a 48 36
write_disc "$dir/photos" b 40 40
mv "$dir/photos/a.pgm" "$dir/photos/b.pgm" "$dir/truth/"

"$mv" mask train --images "$dir/photos" --masks "$dir/truth" -o "$dir/m.mvm" > "$dir/train.txt"
grep -q "2 image/mask pairs, 3-channel model" "$dir/train.txt" || fail "train: $(cat "$dir/train.txt")"
"$mv" mask apply "$dir/photos/a.ppm" --model "$dir/m.mvm" -o "$dir/out" --overlay --json > "$dir/a.json"
for key in pixels foreground_fraction iterations seconds cut_value overlay; do
  grep -q "\"$key\"" "$dir/a.json" || fail "mask apply --json lacks $key"
done
[[ -s "$dir/out/a.png" && -s "$dir/out/a.overlay.png" ]] || fail "no mask or overlay"
"$mv" mask apply "$dir/photos/b.ppm" --rect 2,2,36,36 --no-post -o "$dir/out" > "$dir/b.txt"
grep -q "b.png: 40x40" "$dir/b.txt" || fail "apply: $(cat "$dir/b.txt")"
printf 'a.ppm rect=1,1,46,34\n# a comment\n\nb.ppm model=../m.mvm\n' > "$dir/photos/list.txt"
"$mv" mask apply --list "$dir/photos/list.txt" -o "$dir/batch" --json > "$dir/list.json"
[[ -s "$dir/batch/a.png" && -s "$dir/batch/b.png" ]] || fail "batch: $(cat "$dir/list.json")"
# Every min-cut solver gives the same cuts, so the same mask bytes.
for solver in regions push-relabel; do
  "$mv" mask apply "$dir/photos/b.ppm" --rect 2,2,36,36 --no-post --min-cut-solver "$solver" -o "$dir/$solver" > /dev/null
  cmp -s "$dir/out/b.png" "$dir/$solver/b.png" || fail "--min-cut-solver $solver gives another mask"
done

# Bad input: one error line, exit 1, no mask written.
expect_error() {  # expect_error WORDS ARGS...
  local words=$1; shift
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  grep -q "$words" "$dir/err.txt" || fail "'$*' said: $(cat "$dir/err.txt")"
}
printf 'not an image' > "$dir/bad.ppm"
expect_error "not a PNG, JPEG" mask apply "$dir/bad.ppm" --rect 1,1,5,5 -o "$dir/bad"
cp "$dir/truth/b.pgm" "$dir/seeds.pgm"  # 40 x 40 for a 48 x 36 image
expect_error "is 40 x 40, its image 48 x 36" mask apply "$dir/photos/a.ppm" --seeds "$dir/seeds.pgm" -o "$dir/bad"
mkdir -p "$dir/grey"
cp "$dir/truth/a.pgm" "$dir/grey/a.pgm"
"$mv" mask train --images "$dir/grey" --masks "$dir/truth" -o "$dir/grey.mvm" > /dev/null
expect_error "model is for 1-channel images" mask apply "$dir/photos/a.ppm" --model "$dir/grey.mvm" -o "$dir/bad"
expect_error "min-cut-solver" mask apply "$dir/photos/b.ppm" --rect 2,2,36,36 --min-cut-solver bk -o "$dir/bad"
expect_error "does not lie inside" mask apply "$dir/photos/a.ppm" --rect 40,30,20,20 -o "$dir/bad"
expect_error "rect wants" mask apply "$dir/photos/a.ppm" --rect 1,2,3 -o "$dir/bad"
expect_error "a.ppm: mask: no start" mask apply "$dir/photos/a.ppm" -o "$dir/bad"
# A list's errors name its file and line.
printf 'a.ppm rect=1,1,46,34\n\nb.ppm\n' > "$dir/photos/nostart.txt"
expect_error "nostart.txt:3: mask: no start" mask apply --list "$dir/photos/nostart.txt" -o "$dir/partial"
printf '# masks\na.ppm rect=1,1,46\n' > "$dir/photos/badrect.txt"
expect_error "badrect.txt:2: rect wants" mask apply --list "$dir/photos/badrect.txt" -o "$dir/bad"
printf 'a.ppm colour=red\n' > "$dir/photos/badkey.txt"
expect_error "badkey.txt:1: 'colour=red'" mask apply --list "$dir/photos/badkey.txt" -o "$dir/bad"
printf 'missing.ppm rect=1,1,5,5\n' > "$dir/photos/missing.txt"
expect_error "missing.txt:1: cannot open image" mask apply --list "$dir/photos/missing.txt" -o "$dir/bad"
head -c 40 "$dir/m.mvm" > "$dir/cut.mvm"
expect_error "truncated\|not a .mvm" mask apply "$dir/photos/a.ppm" --model "$dir/cut.mvm" -o "$dir/bad"
expect_error "one-channel image is expected" mask train --images "$dir/truth" --masks "$dir/photos" -o "$dir/bad.mvm"
mkdir -p "$dir/empty"
expect_error "no image in" mask train --images "$dir/empty" --masks "$dir/truth" -o "$dir/bad.mvm"
[[ -z "$(ls -A "$dir/bad" 2>/dev/null)" && ! -e "$dir/bad.mvm" ]] || fail "an output was left after an error"
echo "mask CLI: ok"

#!/usr/bin/env bash
# One command-line dialect: a mistyped verb or option gets the name meant; with --json every failure is one JSON
# object on stdout naming its C API code; both render verbs take the same camera, size and output options; `info`
# says which way its levels count; no help text speaks of anything but the user's work.
# Usage: cli_dialect.sh MEGAVOX
set -euo pipefail
mv=$1
source "$(dirname "$0")/common.sh"

# expect_fail STDERR_PATTERN ARGS...: a non-zero exit whose stderr matches.
expect_fail() {
  local pattern=$1; shift
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  grep -q -- "$pattern" "$dir/err.txt" || fail "'$*' said: $(cat "$dir/err.txt")"
}
expect_fail "^megavox: error: unknown command 'biuld'; did you mean 'build'?$" biuld
expect_fail "unknown command 'bench sotr'; did you mean 'bench sort'?" bench sotr
expect_fail "unknown command 'points rendr'; did you mean 'points render'?" points rendr x.mvx
expect_fail "unknown command 'frobnicate' (commands: " frobnicate
write_tetra_ply "$dir/tetra.ply"
expect_fail "unknown option '--resoluton' for 'megavox build'; did you mean '--resolution'?" \
  build "$dir/tetra.ply" --resoluton 4K -o "$dir/t.mvx"
expect_fail "unknown option '--hieght' for 'megavox render'; did you mean '--height'?" render x.mvx -o y.png --hieght 5
[[ ! -e $dir/t.mvx ]] || fail "a refused command wrote its output"

# --json: one JSON object on stdout, the code by the C API's names, a non-zero exit.
expect_json() {  # expect_json CODE MESSAGE_PATTERN ARGS...
  local code=$1 pattern=$2; shift 2
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  python3 - "$dir/out.txt" "$code" "$pattern" <<'PY' || fail "'$*' printed: $(cat "$dir/out.txt") / $(cat "$dir/err.txt")"
import json, re, sys
text = open(sys.argv[1]).read()
j = json.loads(text)
assert text.count("\n") == 1 and set(j) == {"error", "code"}, text
assert j["code"] == sys.argv[2], j
assert re.search(sys.argv[3], j["error"]), j
PY
}
expect_json MV_ERROR_IO "none.mvx" info "$dir/none.mvx" --json
expect_json MV_ERROR_INVALID_ARGUMENT "^resolution 48 must be a power of two .* \\(--resolution\\)$" \
  build "$dir/tetra.ply" --resolution 48 -o "$dir/t.mvx" --json
expect_json MV_ERROR_INVALID_ARGUMENT "did you mean 'build'" biuld --json
expect_json MV_ERROR_INVALID_ARGUMENT "--resoluton" build "$dir/tetra.ply" --resoluton 4K -o "$dir/t.mvx" --json
expect_json MV_ERROR_INVALID_ARGUMENT "file is required" info --json
expect_json MV_ERROR_UNSUPPORTED_DEVICE "" --device no-such-device-anywhere devices --json
expect_json MV_ERROR_INVALID_ARGUMENT "--eye wants X,Y,Z" render "$dir/none.mvx" -o "$dir/x.png" --eye 1,2 --json

# The render verbs: the same options with the same forms and defaults.
"$mv" build "$dir/tetra.ply" --resolution 64 -o "$dir/t.mvx" --quiet > /dev/null
points_help=$("$mv" points render --help) render_help=$("$mv" render --help)
for opt in "--width UINT=1920" "--height UINT=1080" "--view TEXT=iso" "--eye TEXT" "--target TEXT" "--up TEXT" \
    "--fov FLOAT=40" "--json" "-q,--quiet"; do
  grep -q -- "$opt" <<<"$points_help" || fail "points render --help lacks '$opt'"
  grep -q -- "$opt" <<<"$render_help" || fail "render --help lacks '$opt'"
done
[[ -z $("$mv" render "$dir/t.mvx" -o "$dir/q.png" --width 32 --height 24 -q) && -s $dir/q.png ]] || fail "render -q"
"$mv" render "$dir/t.mvx" -o "$dir/up_axis.png" --width 48 --height 32 --eye 2,1,2 --up y -q
"$mv" render "$dir/t.mvx" -o "$dir/up_vec.png" --width 48 --height 32 --eye 2,1,2 --up 0,1,0 -q
cmp "$dir/up_axis.png" "$dir/up_vec.png" || fail "render --up y differs from --up 0,1,0"

# info: the header counts the rows of its table.
"$mv" info "$dir/t.mvx" > "$dir/info.txt"
grep -q "64^3, 7 levels (voxels 0 .. root 6)" "$dir/info.txt" || fail "info header: $(head -1 "$dir/info.txt")"
rows=$(grep -cE '^  [0-9]+ +[0-9]+ +[0-9]+$' "$dir/info.txt")
[[ $rows == 7 ]] || fail "info shows $rows level rows: $(cat "$dir/info.txt")"

# Help texts speak of the user's work, not of the project's tracker.
for cmd in "" build info render "points build" "points render" "mask apply" "bench points" "bench page-layout"; do
  # shellcheck disable=SC2086
  if "$mv" $cmd --help | grep -qiE "the issue|quoted"; then fail "'megavox $cmd --help' speaks of an issue"; fi
done
echo "CLI dialect: ok"

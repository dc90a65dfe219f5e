#!/usr/bin/env bash
# `megavox points convert` as a user runs it on PDAL's LAZ files (../shared/data/pointcloud_laz): LAZ to
# plain LAS equal to the uncompressed twin's records, --json, and the refusals: an output that is the input, a
# non-.las output, a damaged file (one clear error line naming it, a non-zero exit, nothing left behind).
set -euo pipefail
mv=$1
data=${2:-}
source "$(dirname "$0")/common.sh"
laz=$data/pointcloud_laz
if [[ -z $data || ! -f $laz/simple.laz ]]; then
  echo "points_convert: not run: no ${laz:-../shared/data/pointcloud_laz}/simple.laz (stage ../shared/data)"
  exit 0
fi

records() {  # records FILE: the point records of a plain LAS file, to stdout
  local offset count length
  offset=$(od -An -tu4 -j96 -N4 "$1" | tr -d ' ')
  length=$(od -An -tu2 -j105 -N2 "$1" | tr -d ' ')
  count=$(od -An -tu4 -j107 -N4 "$1" | tr -d ' ')
  tail -c +$((offset + 1)) "$1" | head -c $((count * length))
}

"$mv" points convert "$laz/simple.laz" -o "$dir/simple.las" > "$dir/out.txt"
grep -q "1065 points of 34 bytes" "$dir/out.txt" || fail "summary: $(cat "$dir/out.txt")"
cmp <(records "$dir/simple.las") <(records "$laz/simple.las") || fail "simple.laz's records differ from simple.las's"
"$mv" points convert "$laz/1.2-with-color.copc.laz" -o "$dir/copc.las" --json --threads 1 > "$dir/c.json"
for key in input_format points record_length bytes_written decode_seconds points_per_second; do
  grep -q "\"$key\"" "$dir/c.json" || fail "points convert --json lacks $key"
done
grep -q '"LAZ 1.4, point format 7 COPC (LASzip 3.4, layered chunked, 65 chunks)"' "$dir/c.json" || fail "$(cat "$dir/c.json")"
# A box: only the chunks whose octree node meets it are decoded, and the header counts what was kept.
"$mv" points convert "$laz/1.2-with-color.copc.laz" -o "$dir/part.las" --json \
  --bounds 637000,849000,-1000,638000,850000,1000 > "$dir/part.json"
jq -e '.chunks_read < .chunks and .points_written < .points and .points_written > 0' "$dir/part.json" > /dev/null ||
  fail "bounded COPC read: $(cat "$dir/part.json")"
expect_error() {  # expect_error WORDS ARGS...
  local words=$1; shift
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  grep -q "$words" "$dir/err.txt" || fail "'$*' said: $(cat "$dir/err.txt")"
  [[ $(wc -l < "$dir/err.txt") -eq 1 ]] || fail "more than one line: $(cat "$dir/err.txt")"
}
expect_error "bounds wants" points convert "$laz/simple.laz" -o "$dir/b.las" --bounds 1,2,3
expect_error "bounds wants" points build "$laz/simple.laz" -o "$dir/b.mvx" --bounds 5,0,0,4,1,1
# The plain file builds like any LAS.
"$mv" points build "$dir/copc.las" -o "$dir/copc.mvx" > /dev/null
"$mv" points build "$laz/1.2-with-color.copc.laz" -o "$dir/copc2.mvx" > /dev/null
"$mv" points info "$dir/copc2.mvx" | grep -q "1065 points" || fail "the COPC file's build lost points"

cp "$laz/simple.laz" "$dir/mine.laz"
expect_error "is one of the inputs\|is the input" points convert "$dir/mine.laz" -o "$dir/mine.laz"
cmp -s "$dir/mine.laz" "$laz/simple.laz" || fail "the input was changed"
expect_error "name the output .las or .ply" points convert "$dir/mine.laz" -o "$dir/out"
expect_error "not a point cloud megavox reads" points convert "$dir/out.txt" -o "$dir/x.las"
head -c 9000 "$laz/simple.laz" > "$dir/cut.laz"
expect_error "cut.laz: corrupt LAZ" points convert "$dir/cut.laz" -o "$dir/cut.las"
[[ ! -e $dir/cut.las ]] || fail "a damaged input left an output"
expect_error "cut.laz: corrupt LAZ" points build "$dir/cut.laz" -o "$dir/cut.mvx"
[[ ! -e $dir/cut.mvx ]] || fail "a damaged input left a build"
# To PLY and back: LAZ -> PLY keeps every field by name; PLY -> LAS -> PLY keeps colours exactly and positions
# on the grid the PLY reader chose (within half its step: float32's ulp at the largest coordinate).
"$mv" points convert "$laz/simple.laz" -o "$dir/simple.ply" > /dev/null
for p in "element vertex 1065" "property double x" "property ushort red" "property uchar classification" \
         "property double gps_time" "comment megavox points convert from LAZ 1.2"; do
  head -c 2000 "$dir/simple.ply" | grep -qa "$p" || fail "simple.ply lacks '$p'"
done
lion=$data/pointcloud_lion_takanawa/lion_takanawa.ply
if [[ -f $lion ]]; then
  "$mv" points convert "$lion" -o "$dir/lion.las" > /dev/null
  "$mv" points convert "$dir/lion.las" -o "$dir/lion2.ply" --json > "$dir/l.json"
  grep -q '"input_format": "LAS 1.4, point format 7"' "$dir/l.json" || fail "lion.las: $(cat "$dir/l.json")"
  /usr/bin/python3 - "$lion" "$dir/lion2.ply" <<'PY' || fail "lion.ply -> LAS -> PLY changed positions or colours"
import sys
import numpy as np
def vertices(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    props, count = [], 0
    for line in data[:end].decode().splitlines():
        w = line.split()
        if w[:2] == ["element", "vertex"]: count = int(w[2])
        if w[:1] == ["property"]: props.append((w[2], {"float": "<f4", "double": "<f8", "uchar": "u1", "ushort": "<u2"}[w[1]]))
    return np.frombuffer(data, dtype=np.dtype(props), count=count, offset=end)
a, b = vertices(sys.argv[1]), vertices(sys.argv[2])
big = max(float(np.abs(a[k]).max()) for k in "xyz")
step = 2.0 ** (np.ceil(np.log2(big)) - 24)
ok = len(a) == len(b) and all(np.abs(a[k].astype("f8") - b[k]).max() <= step / 2 for k in "xyz")
ok = ok and all(np.array_equal(a[c].astype("u2"), b[c]) for c in ("red", "green", "blue"))
sys.exit(0 if ok else 1)
PY
fi
expect_error "writes LAS or PLY" points convert "$laz/simple.laz" -o "$dir/x.obj"
expect_error "bounds keeps the points of a LAS or LAZ file" points convert "$laz/simple.laz" -o "$dir/x.ply" --bounds 0,0,0,1,1,1
echo "points_convert: ok"

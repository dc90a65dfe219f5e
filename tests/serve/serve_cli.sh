#!/usr/bin/env bash
# `megavox serve` on loopback as docs/embedding.md's curl session uses it (submit by name and by upload, poll,
# stream, fetch, ray query, render with a view and a camera, a point cloud to .mvx and to a .3tz archive, a
# mask of a photograph), then what it refuses (no or a bad token 401, an oversized body 413, paths leading
# outside --data-dir, malformed JSON and bad fields 400), jobs that fail in the API's own terms while the
# server keeps serving, cancel and delete, the OpenAPI document through swagger-parser, SIGTERM leaving no
# partial file, and a job stopped by --job-timeout. Its inputs are written here (no shared data); the .3tz is
# also read by loaders.gl and the OpenAPI document by swagger-parser where tests/js has its packages.
# Usage: serve_cli.sh MEGAVOX SOURCE_DIR
set -euo pipefail
mv=$1
src=$2
source "$src/tests/cli/common.sh"
source "$src/tests/serve/serve_common.sh"
data=$dir/data
mkdir -p "$data"
write_tetra_ply "$data/tetra.ply"
# a small point cloud: a 10 x 10 x 10 lattice with colours, ascii PLY
write_lattice_ply "$data/lattice.ply" 10 25
files() { node "$src/tests/serve/serve_files.js" "$@"; }
files png "$data/photo.png"   # 48 x 32: a bright 16 x 12 box at (16, 10) on a dark ground
start_server "$data" --max-jobs 2 --max-body 1M --job-timeout 60 --device-memory 512M
[[ $(stat -c %a "$data/token") == 600 ]] || fail "token mode $(stat -c %a "$data/token")"
grep -q "token in $data/token" "$dir/serve.out" || fail "the token's path is not printed"
code() { curl -s -o "$dir/body" -w '%{http_code}' "$@"; }

# auth
[[ $(code "$url/v1/jobs") == 401 ]] || fail "no token: not 401"
[[ $(code -H "Authorization: Bearer wrong$token" "$url/v1/jobs") == 401 ]] || fail "bad token: not 401"
[[ $(code -H "Authorization: Bearer $token" "$url/v1/jobs") == 200 ]] || fail "good token: not 200"

# submit by name, poll, fetch, check the .mvx
job=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":64,"format":"ssvdag"}' "$url/v1/jobs")
id=$(jq -r .id <<< "$job")
final=$(wait_job "$id")
[[ $(jq -r .status <<< "$final") == done && $(jq -r .percentComplete <<< "$final") == 100 ]] || fail "build: $final"
curl -sf "${auth[@]}" -o "$dir/tetra.mvx" "$url/v1/jobs/$id/result"
"$mv" info "$dir/tetra.mvx" | grep -q "64" || fail "the fetched .mvx: $("$mv" info "$dir/tetra.mvx" 2>&1)"

# the progress stream of a finished job: its status, then the stream ends
curl -sfN --max-time 20 "${auth[@]}" "$url/v1/jobs/$id/events" > "$dir/events"
grep -q '^event: status' "$dir/events" && grep -q '"status":"done"' "$dir/events" || fail "events: $(cat "$dir/events")"

# ray queries: one down onto the tetrahedron, one past it (7 f32 in, 32 bytes out each)
node -e 'const f=new Float32Array([0.2,0.2,5, 0,0,-1, Infinity, 3,3,5, 0,0,-1, Infinity]);process.stdout.write(Buffer.from(f.buffer))' > "$dir/rays.bin"
curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$dir/rays.bin" "$url/v1/jobs/$id/rays" -o "$dir/hits.bin"
[[ $(stat -c %s "$dir/hits.bin") == 64 ]] || fail "hits: $(stat -c %s "$dir/hits.bin") bytes"
hits=$(node -e 'const b=require("fs").readFileSync(process.argv[1]);const t0=b.readFloatLE(0),t1=b.readFloatLE(32);console.log((t0>4&&t0<5)+" "+(t1===Infinity)+" "+b.readInt32LE(28))' "$dir/hits.bin")
[[ $hits == "true true 1" ]] || fail "hit records: $hits"
# the fetched .mvx opened as a scene without a build answers the same bytes; the file stays the user's
cp "$dir/tetra.mvx" "$data/fetched.mvx"
open=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"open","input":"fetched.mvx"}' "$url/v1/jobs")
openid=$(jq -r .id <<< "$open")
[[ $(jq -r .status <<< "$(wait_job "$openid")") == done ]] || fail "open: $(curl -s "${auth[@]}" "$url/v1/jobs/$openid")"
curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$dir/rays.bin" "$url/v1/jobs/$openid/rays" -o "$dir/open_hits.bin"
cmp -s "$dir/hits.bin" "$dir/open_hits.bin" || fail "an open job's hits differ from its build's"
[[ $(code "${auth[@]}" "$url/v1/jobs/$openid/result") == 409 ]] || fail "an open job's result: not 409"
[[ $(code "${auth[@]}" -X DELETE "$url/v1/jobs/$openid") == 204 && -f "$data/fetched.mvx" ]] || fail "deleting an open job took its file"
printf 'abc' > "$dir/ragged.bin"
[[ $(code "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$dir/ragged.bin" "$url/v1/jobs/$id/rays") == 400 ]] ||
  fail "ragged rays: not 400"

# upload, then a render of the built scene
up=$(curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$data/tetra.ply" "$url/v1/jobs?kind=build&resolution=32&name=t.ply")
upid=$(jq -r .id <<< "$up")
[[ $(jq -r .status <<< "$(wait_job "$upid")") == done ]] || fail "upload build"
ren=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d "{\"kind\":\"render\",\"scene\":\"$upid\",\"width\":64,\"height\":48}" "$url/v1/jobs")
renid=$(jq -r .id <<< "$ren")
[[ $(jq -r .status <<< "$(wait_job "$renid")") == done ]] || fail "render"
curl -sf "${auth[@]}" -o "$dir/r.png" "$url/v1/jobs/$renid/result"
[[ $(head -c 4 "$dir/r.png" | od -An -tx1 | tr -d ' ') == 89504e47 ]] || fail "the render is no PNG"
# the same scene from a camera, as the CLI's render takes one; the finished job's stage is its status
cam=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' \
  -d "{\"kind\":\"render\",\"scene\":\"$upid\",\"width\":40,\"height\":30,\"eye\":[2,1.5,2],\"target\":[0.3,0.3,0.3],\"fov\":30}" "$url/v1/jobs")
camfinal=$(wait_job "$(jq -r .id <<< "$cam")")
[[ $(jq -r .status <<< "$camfinal") == done && $(jq -r .stage <<< "$camfinal") == done ]] || fail "camera render: $camfinal"
curl -sf "${auth[@]}" -o "$dir/cam.png" "$url/v1/jobs/$(jq -r .id <<< "$cam")/result"
[[ $(head -c 24 "$dir/cam.png" | od -An -tu1 -j16 | tr -s ' ') == " 0 0 0 40 0 0 0 30" ]] || fail "camera render: not 40 x 30"
# no size given: the CLI's render's 1920 x 1080 (depth shading: no shadow or AO rays, a few seconds on a CPU)
big=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d "{\"kind\":\"render\",\"scene\":\"$upid\",\"shading\":\"depth\"}" "$url/v1/jobs")
[[ $(jq -r .status <<< "$(wait_job "$(jq -r .id <<< "$big")")") == done ]] || fail "default-size render"
curl -sf "${auth[@]}" -o "$dir/big.png" "$url/v1/jobs/$(jq -r .id <<< "$big")/result"
[[ $(head -c 24 "$dir/big.png" | od -An -tu1 -j16 | tr -s ' ') == " 0 0 7 128 0 0 4 56" ]] || fail "default render: not 1920 x 1080"

# a point cloud by name to a .mvx hierarchy, and to a 3D Tiles archive (.3tz)
pts=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"points","input":"lattice.ply","max_node_points":100}' "$url/v1/jobs")
ptsid=$(jq -r .id <<< "$pts")
ptsfinal=$(wait_job "$ptsid")
[[ $(jq -r .status <<< "$ptsfinal") == done && $(jq -r .stage <<< "$ptsfinal") == done ]] || fail "points: $ptsfinal"
curl -sf "${auth[@]}" -o "$dir/lattice.mvx" "$url/v1/jobs/$ptsid/result"
"$mv" points info "$dir/lattice.mvx" | grep -q "1000 points" || fail "points .mvx: $("$mv" points info "$dir/lattice.mvx" 2>&1)"
# the coloured cloud as voxels, and a ray's colour beside its hit (?colour=rgba): the lattice point (5.5, 5.25, 9)
# fills its voxel alone at 16^3 (a voxel is 9/16 wide), so a ray down onto it sees 125, 125, 225
vox=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"lattice.ply","resolution":16,"grid_origin":"min"}' "$url/v1/jobs")
voxid=$(jq -r .id <<< "$vox")
[[ $(jq -r .status <<< "$(wait_job "$voxid")") == done ]] || fail "coloured cloud build"
node -e 'const f=new Float32Array([5.5,5.25,20, 0,0,-1, Infinity, 30,30,20, 0,0,-1, Infinity]);process.stdout.write(Buffer.from(f.buffer))' > "$dir/crays.bin"
curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$dir/crays.bin" "$url/v1/jobs/$voxid/rays?colour=rgba" -o "$dir/chits.bin"
[[ $(stat -c %s "$dir/chits.bin") == 72 ]] || fail "coloured hits: $(stat -c %s "$dir/chits.bin") bytes"
[[ $(od -An -tu1 -j64 "$dir/chits.bin" | tr -s ' ') == " 125 125 225 255 0 0 0 0" ]] || fail "hit colours: $(od -An -tu1 -j64 "$dir/chits.bin")"
[[ $(code "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$dir/crays.bin" "$url/v1/jobs/$voxid/rays?colour=rgb") == 400 ]] ||
  fail "colour=rgb: not 400"
tz=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"points","input":"lattice.ply","format":"3dtiles","max_node_points":100}' "$url/v1/jobs")
tzid=$(jq -r .id <<< "$tz")
[[ $(jq -r .status <<< "$(wait_job "$tzid")") == done ]] || fail "points 3dtiles"
[[ $(curl -sf "${auth[@]}" -o "$dir/lattice.3tz" -w '%{content_type}' "$url/v1/jobs/$tzid/result") == application/vnd.maxar.archive.3tz+zip ]] ||
  fail "the .3tz's content type"
files 3tz "$dir/lattice.3tz" > "$dir/3tz.txt" || fail "the .3tz breaks the archive's rules"
grep -q '\.glb$' "$dir/3tz.txt" || fail "the .3tz holds no tile: $(cat "$dir/3tz.txt")"
[[ -z $(ls "$data/jobs/$tzid" | grep -v '^result.3tz$') ]] || fail "the tileset folder stays: $(ls "$data/jobs/$tzid")"
if [[ -d "$src/tests/js/node_modules/@loaders.gl/3d-tiles" ]]; then  # an independent reader, through the index
  node "$src/tests/js/check_3tz.mjs" "$dir/lattice.3tz" 1000 > "$dir/3tz.json" || fail "loaders.gl: $(cat "$dir/3tz.json")"
else
  echo "loaders.gl not installed (npm ci in tests/js): the .3tz not read by an independent reader"
fi
# 3D Tiles 1.0 on request: .pnts tiles
tz10=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' \
  -d '{"kind":"points","input":"lattice.ply","format":"3dtiles","tiles_version":"1.0","max_node_points":100}' "$url/v1/jobs")
tz10id=$(jq -r .id <<< "$tz10")
[[ $(jq -r .status <<< "$(wait_job "$tz10id")") == done ]] || fail "points 3dtiles 1.0"
curl -sf "${auth[@]}" -o "$dir/lattice10.3tz" "$url/v1/jobs/$tz10id/result" || fail "the 1.0 archive"
files 3tz "$dir/lattice10.3tz" > "$dir/3tz10.txt" || fail "the 1.0 .3tz breaks the archive's rules"
grep -q '\.pnts$' "$dir/3tz10.txt" || fail "the 1.0 .3tz holds no .pnts tile: $(cat "$dir/3tz10.txt")"
# an uploaded cloud goes the same way
upts=$(curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$data/lattice.ply" "$url/v1/jobs?kind=points&depth=3")
[[ $(jq -r .status <<< "$(wait_job "$(jq -r .id <<< "$upts")")") == done ]] || fail "uploaded points"

# a mask of a photograph from a box: the box's inside is foreground, the ground background
msk=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"mask","input":"photo.png","rect":[12,6,24,20]}' "$url/v1/jobs")
mskid=$(jq -r .id <<< "$msk")
mskfinal=$(wait_job "$mskid")
[[ $(jq -r .status <<< "$mskfinal") == done && $(jq -r .stage <<< "$mskfinal") == done ]] || fail "mask: $mskfinal"
curl -sf "${auth[@]}" -o "$dir/mask.png" "$url/v1/jobs/$mskid/result"
[[ $(files grey "$dir/mask.png" 24,16 2,2 45,30) == "48x32 255 0 0" ]] || fail "mask: $(files grey "$dir/mask.png" 24,16 2,2 45,30)"
# uploaded, with the box in the query
umsk=$(curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$data/photo.png" "$url/v1/jobs?kind=mask&rect=12,6,24,20&name=p.png")
[[ $(jq -r .status <<< "$(wait_job "$(jq -r .id <<< "$umsk")")") == done ]] || fail "uploaded mask"

# refusals
head -c 2000000 /dev/zero > "$dir/big.bin"
[[ $(code "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$dir/big.bin" "$url/v1/jobs?kind=build") == 413 ]] ||
  fail "2 MB over --max-body 1M: not 413"
json_code() { code "${auth[@]}" -H 'Content-Type: application/json' -d "$1" "$url/v1/jobs"; }
ln -s /etc/hostname "$data/out.ply"
for input in ../tetra.ply /etc/hostname out.ply sub/../../x.ply; do
  [[ $(json_code "{\"kind\":\"build\",\"input\":\"$input\"}") == 400 ]] || fail "input $input: not refused"
  grep -Eq 'outside|relative|\.\.' "$dir/body" || fail "input $input: $(cat "$dir/body")"
done
[[ $(json_code '{"kind":"build",') == 400 ]] && grep -q 'malformed JSON' "$dir/body" || fail "malformed JSON: $(cat "$dir/body")"
[[ $(json_code '{"kind":"build","input":"tetra.ply","resolution":48}') == 400 ]] && grep -q 'power of two' "$dir/body" ||
  fail "resolution 48: $(cat "$dir/body")"
[[ $(json_code '{"kind":"bake"}') == 400 ]] || fail "kind bake: not 400"
[[ $(jq -r .code "$dir/body") == MV_ERROR_INVALID_ARGUMENT ]] || fail "kind bake: code $(cat "$dir/body")"
# a number past 64 bits: nlohmann throws out_of_range, not parse_error (found by fuzz_job_request)
[[ $(json_code '{"kind":"build","resolution":64e222222223}') == 400 ]] && grep -q 'malformed JSON' "$dir/body" ||
  fail "64e222222223: $(cat "$dir/body")"
[[ $(code "${auth[@]}" "$url/v1/jobs/0123456789abcdef") == 404 ]] || fail "unknown job: not 404"
# new fields, each refused with its key named
while IFS='|' read -r body words; do
  [[ $(json_code "$body") == 400 ]] && jq -r .error "$dir/body" | grep -qF -- "$words" || fail "$body: $(cat "$dir/body")"
done <<'JOBS'
{"kind":"points","input":"lattice.ply","format":"ssvdag"}|"format" 'ssvdag': choose mvx, 3dtiles
{"kind":"points","input":"lattice.ply","depth":40}|"depth" must be from 0 to 21
{"kind":"points","input":"lattice.ply","rect":[0,0,1,1]}|a points job takes no "rect"
{"kind":"mask","input":"photo.png"}|a mask job needs a start
{"kind":"mask","input":"photo.png","rect":[1,2,3]}|"rect" must be an array of four integers
{"kind":"mask","input":"photo.png","seeds":"../x.png"}|".." is refused
{"kind":"mask","input":"photo.png","model":"none.mvm"}|no such file
{"kind":"render","scene":"0123456789abcdef","eye":[1,1]}|"eye" must be an array of three numbers
{"kind":"render","scene":"0123456789abcdef","target":[0,0,0]}|"target" and "up" go with "eye"
{"kind":"render","scene":"0123456789abcdef","fov":200}|"fov" must lie between 0 and 180
{"kind":"build","input":"tetra.ply","cube":12}|"cube" must be 0 (always in core) or a power of two
JOBS
[[ $(code "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary @"$data/photo.png" "$url/v1/jobs?kind=mask&rect=1,2,x,4") == 400 ]] &&
  grep -q 'rect' "$dir/body" || fail "upload rect=1,2,x,4: $(cat "$dir/body")"

# a job whose input is garbage fails with its message; the server keeps serving
bad=$(curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary 'ply
format ascii 1.0
element vertex two' "$url/v1/jobs?kind=build&resolution=16&name=bad.ply")
badfinal=$(wait_job "$(jq -r .id <<< "$bad")")
[[ $(jq -r .status <<< "$badfinal") == failed && -n $(jq -r .message <<< "$badfinal") && $(jq -r .stage <<< "$badfinal") == failed ]] ||
  fail "bad input: $badfinal"
[[ $(jq -r .code <<< "$badfinal") == MV_ERROR_INPUT ]] || fail "bad input: no MV_ERROR_INPUT code: $badfinal"
# failures name the job's keys, never the CLI's flags: a box past the image, cubes too many for the budget
past=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"mask","input":"photo.png","rect":[40,20,20,20]}' "$url/v1/jobs")
pastfinal=$(wait_job "$(jq -r .id <<< "$past")")
[[ $(jq -r .status <<< "$pastfinal") == failed && $(jq -r .message <<< "$pastfinal") == *'"rect" [40, 20, 20, 20] reaches past the 48 x 32 image'* ]] ||
  fail "rect past the image: $pastfinal"
cubes=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":2097152,"cube":8}' "$url/v1/jobs")
cubesfinal=$(wait_job "$(jq -r .id <<< "$cubes")")
cubesmsg=$(jq -r .message <<< "$cubesfinal")
[[ $(jq -r .status <<< "$cubesfinal") == failed && $cubesmsg == *'raise "cube"'* && $cubesmsg != *--* ]] || fail "cube advice: $cubesfinal"
notcloud=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"points","input":"photo.png"}' "$url/v1/jobs")
[[ $(jq -r .status <<< "$(wait_job "$(jq -r .id <<< "$notcloud")")") == failed ]] || fail "points from a PNG"
again=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":16}' "$url/v1/jobs")
[[ $(jq -r .status <<< "$(wait_job "$(jq -r .id <<< "$again")")") == done ]] || fail "no build after the failed one"

# cancel a running build: cancelled (or done first), nothing left of its result
long=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":8192}' "$url/v1/jobs")
lid=$(jq -r .id <<< "$long")
curl -sf -X POST -d '' "${auth[@]}" "$url/v1/jobs/$lid/cancel" > /dev/null
lfinal=$(wait_job "$lid")
case $(jq -r .status <<< "$lfinal") in
  cancelled) [[ -z $(ls "$data/jobs/$lid") ]] || fail "a cancelled job left $(ls "$data/jobs/$lid")" ;;
  done) ;;
  *) fail "cancel: $lfinal" ;;
esac

# list and delete
jq -e --arg id "$id" '.jobs | map(.id) | index($id)' <<< "$(curl -sf "${auth[@]}" "$url/v1/jobs")" > /dev/null || fail "list lacks $id"
[[ $(code -X DELETE "${auth[@]}" "$url/v1/jobs/$id") == 204 ]] || fail "delete: not 204"
[[ $(code "${auth[@]}" "$url/v1/jobs/$id") == 404 && ! -e "$data/jobs/$id" ]] || fail "a deleted job stays"

# the OpenAPI document, validated by swagger-parser (tests/js)
curl -sf "${auth[@]}" "$url/v1/openapi.json" -o "$dir/openapi.json"
if [[ -d "$src/tests/js/node_modules/@apidevtools/swagger-parser" ]]; then
  node "$src/tests/js/check_openapi.mjs" "$dir/openapi.json" || fail "swagger-parser rejects /v1/openapi.json"
else
  echo "swagger-parser not installed (npm ci in tests/js): /v1/openapi.json not validated"
fi

# SIGTERM during a build: the server stops, exit 0, no partial file
slow=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":8192}' "$url/v1/jobs")
sid=$(jq -r .id <<< "$slow")
sleep 0.5
kill -TERM $pid
wait $pid || fail "serve exited $? after SIGTERM: $(tail -3 "$dir/serve.err")"
grep -q 'stopped' "$dir/serve.err" || fail "no 'stopped' line"
[[ -z $(find "$data" -name '*.tmp') ]] || fail "partial files: $(find "$data" -name '*.tmp')"
[[ -e "$data/jobs/$sid/result.mvx" || ! -e "$data/jobs/$sid" ]] || fail "the unfinished job's folder stays: $(ls -R "$data/jobs/$sid")"

# a job past --job-timeout is stopped at its next progress point and failed, saying why (a tetrahedron at 8192:
# seconds of work even with every kernel already compiled; at 2048 a warm machine finished it inside the second)
mkdir -p "$dir/data2"
write_tetra_ply "$dir/data2/tetra.ply"
start_server "$dir/data2" --job-timeout 1 --device-memory 512M
slow=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":8192}' "$url/v1/jobs")
tfinal=$(wait_job "$(jq -r .id <<< "$slow")")
[[ $(jq -r .status <<< "$tfinal") == failed && $(jq -r .message <<< "$tfinal") == *timeout* ]] || fail "job timeout: $tfinal"
echo "serve: session, refusals, failure, cancel, delete, OpenAPI, SIGTERM and the job timeout all as expected"

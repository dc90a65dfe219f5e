#!/usr/bin/env bash
# `megavox serve` on loopback as the README's curl session uses it (submit by name and by upload, poll,
# stream, fetch, ray query, render), then what it refuses (no or a bad token 401, an oversized body 413,
# paths leading outside --data-dir, malformed JSON 400), a job that fails while the server keeps serving,
# cancel and delete, the OpenAPI document through swagger-parser, SIGTERM leaving no partial file, and a job
# stopped by --job-timeout.
# Usage: serve_cli.sh MEGAVOX SOURCE_DIR
set -euo pipefail
mv=$1
src=$2
source "$src/tests/cli/common.sh"
source "$src/tests/serve/serve_common.sh"
data=$dir/data
mkdir -p "$data"
write_tetra_ply "$data/tetra.ply"
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
# a number past 64 bits: nlohmann throws out_of_range, not parse_error (found by fuzz_job_request)
[[ $(json_code '{"kind":"build","resolution":64e222222223}') == 400 ]] && grep -q 'malformed JSON' "$dir/body" ||
  fail "64e222222223: $(cat "$dir/body")"
[[ $(code "${auth[@]}" "$url/v1/jobs/0123456789abcdef") == 404 ]] || fail "unknown job: not 404"

# a job whose input is garbage fails with its message; the server keeps serving
bad=$(curl -sf "${auth[@]}" -H 'Content-Type: application/octet-stream' --data-binary 'ply
format ascii 1.0
element vertex two' "$url/v1/jobs?kind=build&resolution=16&name=bad.ply")
badfinal=$(wait_job "$(jq -r .id <<< "$bad")")
[[ $(jq -r .status <<< "$badfinal") == failed && -n $(jq -r .message <<< "$badfinal") ]] || fail "bad input: $badfinal"
again=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":16}' "$url/v1/jobs")
[[ $(jq -r .status <<< "$(wait_job "$(jq -r .id <<< "$again")")") == done ]] || fail "no build after the failed one"

# cancel a running build: cancelled (or done first), nothing left of its result
long=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":2048}' "$url/v1/jobs")
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
slow=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":2048}' "$url/v1/jobs")
sid=$(jq -r .id <<< "$slow")
sleep 0.5
kill -TERM $pid
wait $pid || fail "serve exited $? after SIGTERM: $(tail -3 "$dir/serve.err")"
grep -q 'stopped' "$dir/serve.err" || fail "no 'stopped' line"
[[ -z $(find "$data" -name '*.tmp') ]] || fail "partial files: $(find "$data" -name '*.tmp')"
[[ -e "$data/jobs/$sid/result.mvx" || ! -e "$data/jobs/$sid" ]] || fail "the unfinished job's folder stays: $(ls -R "$data/jobs/$sid")"

# a job past --job-timeout is stopped at its next progress point and failed, saying why
mkdir -p "$dir/data2"
write_tetra_ply "$dir/data2/tetra.ply"
start_server "$dir/data2" --job-timeout 1 --device-memory 512M
slow=$(curl -sf "${auth[@]}" -H 'Content-Type: application/json' -d '{"kind":"build","input":"tetra.ply","resolution":2048}' "$url/v1/jobs")
tfinal=$(wait_job "$(jq -r .id <<< "$slow")")
[[ $(jq -r .status <<< "$tfinal") == failed && $(jq -r .message <<< "$tfinal") == *timeout* ]] || fail "job timeout: $tfinal"
echo "serve: session, refusals, failure, cancel, delete, OpenAPI, SIGTERM and the job timeout all as expected"

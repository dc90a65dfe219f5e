# What the serve test scripts share (sourced after tests/cli/common.sh): start a server, its URL and token,
# curl with the token, and waiting for a job.

# start_server DATA_DIR [SERVE OPTIONS...]: runs `megavox serve` on a free loopback port in the background;
# sets pid, url, token, auth (curl's header options).
start_server() {
  local data=$1
  shift
  mkdir -p "$data"
  "$mv" serve --listen 127.0.0.1:0 --data-dir "$data" "$@" > "$dir/serve.out" 2> "$dir/serve.err" &
  pid=$!
  trap 'kill -TERM $pid 2>/dev/null || true; wait $pid 2>/dev/null || true; rm -rf "$dir"' EXIT
  for _ in $(seq 300); do
    grep -q '^listening' "$dir/serve.out" 2>/dev/null && break
    kill -0 $pid 2>/dev/null || fail "serve exited: $(cat "$dir/serve.err")"
    sleep 0.1
  done
  url=$(awk '/^listening/ {print $2; exit}' "$dir/serve.out")
  [[ $url =~ ^http://127\.0\.0\.1:[0-9]+$ ]] || fail "first line: $(head -1 "$dir/serve.out")"
  token=$(cat "$data/token")
  auth=(-H "Authorization: Bearer $token")
}

# wait_job ID: polls until the job ends; prints its final status JSON.
wait_job() {
  local s
  for _ in $(seq 600); do
    s=$(curl -sf "${auth[@]}" "$url/v1/jobs/$1") || fail "status of $1"
    case $(jq -r .status <<< "$s") in done|failed|cancelled) echo "$s"; return ;; esac
    sleep 0.1
  done
  fail "job $1 did not end: $s"
}

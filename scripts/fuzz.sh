#!/usr/bin/env bash
# Fuzzes megavox's readers of untrusted bytes (fuzz/: one libFuzzer target per reader) with ASan and UBSan.
# Usage: scripts/fuzz.sh SECONDS [TARGET...]     (all targets by default: fuzz/fuzz_*.cpp)
#
# Installs what it needs (scripts/setup.sh --fuzz), builds the targets with clang into build-fuzz/
# (-DMEGAVOX_FUZZ=ON), then runs each for SECONDS on a copy of its seed corpus (fuzz/corpus/TARGET, which is
# never written; the grown copy is build-fuzz/corpus/TARGET, fresh each run). Prints one line per target:
# executions, crashes (0, or the paths of their inputs under build-fuzz/artifacts/TARGET/, kept until that
# target's next run) and new coverage (inputs the corpus grew by: the fork parent's corp: figures; its final cov:
# and ft: figures). Full logs: build-fuzz/logs/TARGET.log. Exit status 1 when any target found a crash, a
# leak, a timeout (an input over 10 s), an out-of-memory (over 2 GiB) or a failed MV_FUZZ_CHECK. A slow input
# (slow-unit-*) that runs again in under 1 s is listed apart as a stall of the machine, not a finding.
# Every target runs in libFuzzer's fork mode with one worker per core (-fork=N: the parent merges their corpora
# and counts their executions), its scratch input files on /dev/shm where that exists (the readers take paths).
# fuzz_vdb is the exception for the last two: OpenVDB's own time and memory on a damaged file are unbounded
# (third-party; BENCHMARKS.md, "Fuzzing"), so its run records such inputs (build-fuzz/artifacts/fuzz_vdb/oom-*,
# timeout-*), counts them apart and goes on. Its crashes are run again after the run: one whose first frame in
# OpenVDB or in megavox's sources is OpenVDB's is third-party (counted apart, input kept: BENCHMARKS.md
# "Fuzzing"), any other fails. Its per-input leak checks are off as well
# (-detect_leaks=0): every damaged file leaks a node inside libopenvdb (third-party, suppressed), so libFuzzer
# would re-run nearly every input under a full heap scan (10x slower); LSan still checks each job at its exit.
# Nor does it get libFuzzer's RSS limit: those leaks add up over a long job past any limit, and on reaching it
# clang 14's runtime printed its heap profile from a stopped world and deadlocked, hanging the run (its
# -malloc_limit_mb of 2 GiB per allocation stays). Every run has a watchdog: 5 minutes past SECONDS, the target
# and its jobs are stopped and the run counts as failed.
# Reproduce a crash: build-fuzz/TARGET build-fuzz/artifacts/TARGET/crash-...
# Re-make the committed seeds: cmake --build build-fuzz --target make_seeds && build-fuzz/make_seeds fuzz/corpus
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { echo "usage: scripts/fuzz.sh SECONDS [TARGET...]  (targets: $(echo "${all[@]}"))" >&2; exit 2; }
all=()
for f in fuzz/fuzz_*.cpp; do all+=("$(basename "$f" .cpp)"); done
[[ $# -ge 1 && $1 =~ ^[1-9][0-9]*$ ]] || usage
seconds=$1
shift
targets=("$@")
((${#targets[@]})) || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz: unknown target '$t'" >&2; usage; }
done

scripts/setup.sh --fuzz
generator=()
[[ ! -f build-fuzz/CMakeCache.txt ]] && command -v ninja >/dev/null && generator=(-G Ninja)
CC=clang CXX=clang++ cmake -S . -B build-fuzz "${generator[@]}" -DMEGAVOX_FUZZ=ON >/dev/null
cmake --build build-fuzz --parallel "$(nproc)" --target "${targets[@]}"

# Targets whose wrapped library may take unbounded time or memory on a damaged file (see above).
resource_third_party=" fuzz_vdb "

# Whether the crash input $2 of target $1, run again, stops first in OpenVDB (its library or its headers) rather
# than in megavox's sources.
openvdb_crash() {
  local first
  first=$(ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 timeout 60 build-fuzz/"$1" "$2" 2>&1 |
    grep -E '^ +#[0-9]+ 0x[0-9a-f]+ in ' | grep -m1 -E 'libopenvdb|/usr/include/openvdb/|/host/|/fuzz/fuzz_' || true)
  [[ $first =~ libopenvdb|/usr/include/openvdb/ ]]
}

# Whether the slow input $2 of target $1 runs again in under a second: then it was the machine that stalled
# (this VM pauses both cores now and then), not the reader.
stalled() {
  local start=$EPOCHREALTIME
  ASAN_OPTIONS=detect_leaks=0 timeout 10 build-fuzz/"$1" "$2" >/dev/null 2>&1 || return 1
  awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { exit !(b - a < 1) }'
}

mkdir -p build-fuzz/logs
scratch=${TMPDIR:-/tmp}
[[ -d /dev/shm && -w /dev/shm ]] && scratch=/dev/shm
failed=0
summary=()
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t artifacts=build-fuzz/artifacts/$t log=build-fuzz/logs/$t.log
  rm -rf "$corpus" "$artifacts"
  mkdir -p "$corpus" "$artifacts"
  if [[ -d fuzz/corpus/$t ]]; then cp fuzz/corpus/"$t"/* "$corpus"/; fi
  # LAZ has no writer here to make seeds with: PDAL's small test files seed it, where ../shared is staged.
  if [[ $t == fuzz_laz && -d ../shared/data/pointcloud_laz ]]; then
    find ../shared/data/pointcloud_laz -name '*.laz' -size -64k -exec cp {} "$corpus"/ \;
  fi
  echo "fuzz: $t for ${seconds} s (log: $log)" >&2
  third=0 mode=(-fork="$(nproc)")
  if [[ $resource_third_party == *" $t "* ]]; then
    third=1
    mode+=(-ignore_ooms=1 -ignore_timeouts=1 -ignore_crashes=1 -detect_leaks=0 -rss_limit_mb=0 -malloc_limit_mb=2048)
  else
    mode+=(-rss_limit_mb=2048)
  fi
  rc=0
  # timeout signals the target's whole process group (its fork-mode jobs too)
  TMPDIR=$scratch UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ASAN_OPTIONS=detect_leaks=1 \
    timeout -k 30 $((seconds + 300)) build-fuzz/"$t" "${mode[@]}" -max_total_time="$seconds" -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" >"$log" 2>&1 || rc=$?
  watchdog=0
  ((rc == 124 || rc == 137)) && watchdog=1
  # the parent prints "#EXECS: cov: C ft: F corp: N ..." per finished job
  execs=$(grep -oE '^#[0-9]+:' "$log" | tail -1 | tr -d '#:')
  first=$(grep -oE '^#[0-9]+: cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' "$log" | head -1 | awk '{print $NF}')
  last=$(grep -oE '^#[0-9]+: cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' "$log" | tail -1 | awk '{print $NF}')
  new=$(( ${last:-0} - ${first:-0} ))
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 | sed 's/: /=/g')
  mapfile -t found < <(find "$artifacts" -type f | sort)
  findings=() resources=() stalls=()
  for a in "${found[@]}"; do
    if [[ $(basename "$a") == slow-unit-* ]] && stalled "$t" "$a"; then stalls+=("$a"); continue; fi
    if ((third)) && { [[ $(basename "$a") =~ ^(oom|timeout|slow-unit)- ]] ||
                      { [[ $(basename "$a") == crash-* ]] && openvdb_crash "$t" "$a"; }; }; then
      resources+=("$a")
    else
      findings+=("$a")
    fi
  done
  if ((watchdog)); then
    failed=1
    crashes="? (stopped by the watchdog $((seconds + 300)) s in: a job hung; see $log)"
  elif ((${#findings[@]})); then
    failed=1
    crashes="${#findings[@]}: ${findings[*]}"
  elif ((rc != 0)) && ! ((third && ${#resources[@]})); then
    failed=1
    crashes="? (exit status $rc, no input saved: see $log)"
  else
    crashes=0
  fi
  ((${#stalls[@]})) && crashes+="   slow inputs that rerun in under 1 s (machine stalls) ${#stalls[@]}"
  ((${#resources[@]})) && crashes+="   third-party (OpenVDB) oom/timeout/crash inputs ${#resources[@]} (in $artifacts)"
  summary+=("$(printf '%-18s executions %10s   crashes %s   new coverage %s inputs (%s)' "$t" "${execs:-0}" "$crashes" "$new" "${cov:-no cov line}")")
  echo "${summary[-1]}"
done
echo "fuzz: ${#targets[@]} targets, ${seconds} s each:"
printf '  %s\n' "${summary[@]}"
exit "$failed"

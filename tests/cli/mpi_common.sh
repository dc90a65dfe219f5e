# What the MPI test scripts share (sourced after common.sh): mpirun on this machine only (shared memory and
# loopback, never another interface), oversubscribed, as root where the tests run so; and the killed-rank check.
if ! command -v mpirun >/dev/null; then echo "$mpi_test: no mpirun (scripts/setup.sh installs openmpi-bin)"; exit 0; fi
if "$megavox" --version | grep -q "MPI: not built in"; then echo "$mpi_test: megavox built without MPI"; exit 0; fi
export OMPI_MCA_btl=self,vader OMPI_MCA_oob_tcp_if_include=lo OMPI_MCA_btl_tcp_if_include=lo
export OMPI_MCA_rmaps_base_oversubscribe=1
[[ $(id -u) -eq 0 ]] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# expect_killed_rank_ends_run OUTPUT ARGS...: `mpirun -np 3 megavox ARGS... -o OUTPUT` with one rank killed once
# all three run: mpirun ends the others, the status is non-zero within 30 s, and nothing named like OUTPUT is left.
expect_killed_rank_ends_run() {
  local out=$1 run victim start
  shift
  mpirun -np 3 "$megavox" "$@" -q -o "$out" > "$dir/kill.txt" 2>&1 &
  run=$!
  ranks() { pgrep -f -- "^$megavox .*-o $out" || true; }
  # Each rank is stopped as soon as it is seen, so that none can finish before one is killed (no rank finishes
  # alone: the first collective waits for all three); then one is killed and the others go on.
  for _ in $(seq 400); do
    for pid in $(ranks); do kill -STOP "$pid" 2> /dev/null || true; done
    (($(ranks | wc -l) >= 3)) && break
    sleep 0.02
  done
  victim=$(ranks | tail -1)
  [[ -n "$victim" ]] || fail "no rank to kill: $(cat "$dir/kill.txt")"
  kill -9 "$victim"
  for pid in $(ranks); do kill -CONT "$pid" 2> /dev/null || true; done
  start=$SECONDS
  if wait "$run"; then fail "mpirun succeeded with a rank killed"; fi
  ((SECONDS - start <= 30)) || fail "the run took $((SECONDS - start)) s to end after a rank was killed"
  [[ -z $(ranks) ]] || fail "ranks left running: $(ranks)"
  [[ -z $(ls "$(dirname "$out")" | grep "$(basename "$out")") ]] || fail "output left after a killed rank: $(ls "$dir")"
}

#!/usr/bin/env bash
# Compiles one layering probe as a source of its target would be (that target's include folders) and checks the
# outcome: "allowed" must compile; "forbidden" must fail because the header is not on the path (any other
# error would prove nothing about the layers).
# Usage: compile_probe.sh allowed|forbidden COMPILER PROBE.cpp -I... [-I...]
set -uo pipefail
expect=$1 cxx=$2 probe=$3
shift 3
out=$("$cxx" -std=c++20 -fsyntax-only "$@" "$probe" 2>&1)
rc=$?
name=$(basename "$probe")
if [[ $expect == allowed ]]; then
  if ((rc == 0)); then echo "layering: $name compiles, as it may"; exit 0; fi
  echo "layering: $name should compile with its target's include folders but did not:"; echo "$out"; exit 1
fi
if ((rc != 0)) && grep -qE "No such file or directory|file not found" <<<"$out"; then
  echo "layering: $name is refused, as it must be: $(grep -m1 -E 'No such file|file not found' <<<"$out")"
  exit 0
fi
if ((rc == 0)); then echo "layering: $name compiled, but its include crosses a layer the build must refuse"; exit 1; fi
echo "layering: $name failed for another reason than a missing header:"; echo "$out"; exit 1

#!/usr/bin/env bash
# Runs every libFuzzer target of tests/fuzz for SECONDS each (make fuzz-smoke:
# 20 s, part of make test; make fuzz: FUZZ_SECONDS, 600 by default).
#
#   tests/fuzz/run.sh SECONDS [BUILD_DIR]        (BUILD_DIR default build/fuzz)
#
# Each target starts from its committed seeds (tests/fuzz/corpus/<target>,
# read only) plus what earlier runs found (BUILD_DIR/corpus/<target>, where
# new inputs are written). A crash, a sanitizer report, a timeout (10 s per
# input) or an out-of-memory stops the target with its input saved as
# BUILD_DIR/artifacts/<target>-crash-<sha1>, and this script fails.
# One summary line per target: executions, executions/s, coverage.
set -uo pipefail
cd "$(dirname "$0")/../.."

seconds=${1:?usage: tests/fuzz/run.sh SECONDS [BUILD_DIR]}
build=${2:-build/fuzz}
targets=(fuzz_node_config fuzz_sensors fuzz_commands fuzz_exec_step fuzz_pil_frame fuzz_mekf_step fuzz_momentum_step
         fuzz_node_direct fuzz_fdir_step)
failed=0
for t in "${targets[@]}"; do
  exe="$build/fuzz/$t"
  if [ ! -x "$exe" ]; then
    echo "fuzz: $exe missing (make build-fuzz)" >&2
    exit 1
  fi
  work="$build/corpus/$t"
  mkdir -p "$work" "$build/artifacts"
  log="$build/$t.log"
  "$exe" -max_total_time="$seconds" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$build/artifacts/$t-" "$work" "tests/fuzz/corpus/$t" > "$log" 2>&1
  rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  cov=$(grep -Eo 'cov: [0-9]+' "$log" | tail -1)
  if [ "$rc" -ne 0 ]; then
    echo "fuzz: FAIL $t (exit $rc), log $log:" >&2
    grep -E 'ERROR|runtime error|invariant|Test unit written|deadly signal' "$log" | head -20 >&2
    failed=1
  else
    echo "fuzz: ok   $t: ${seconds} s, ${execs:-?} executions, ${rate:-?} exec/s, ${cov:-cov: ?}"
  fi
done
exit "$failed"

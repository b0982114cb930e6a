#!/usr/bin/env bash
# A short libFuzzer run of every fuzz target (tests/fuzz/, docs/FUZZING.md), two at a time on the two
# cores, each from its committed seeds and kept regressions in a scratch corpus (the fuzzer's own
# additions stay out of the repository). Any finding (crash, sanitizer report, timeout, a reader's
# broken promise) fails the run and prints the input in base64, to be kept under
# tests/fuzz/regressions/<target>/ once the reader is fixed.
#
# Usage: tools/fuzz-smoke.sh <directory of the fuzz_* executables> [seconds per target, default 10]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(cd "$1" && pwd)
seconds=${2:-10}
targets=(scene vs3 obj ply off stl ies ldt)
work=$(mktemp -d /tmp/lambert-fuzz-smoke.XXXXXX)
trap 'rm -rf "$work"' EXIT

# The options of docs/FUZZING.md: inputs up to 64 KiB, 10 s per input, 2 GiB of memory per process.
run_one() {
  local t=$1
  mkdir -p "$work/corpus-$t"
  cp tests/fuzz/"$t"/* "$work/corpus-$t/"
  if [ -d tests/fuzz/regressions/"$t" ]; then cp tests/fuzz/regressions/"$t"/* "$work/corpus-$t/"; fi
  "$bin/fuzz_$t" "$work/corpus-$t" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$work/finding-$t-" -print_final_stats=1 > "$work/$t.log" 2>&1
}

failed=()
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  pids=()
  for t in "${targets[@]:i:2}"; do run_one "$t" & pids+=("$!:$t"); done
  for p in "${pids[@]}"; do
    t=${p#*:}
    if wait "${p%%:*}"; then
      runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/$t.log")
      cov=$(grep -o 'cov: [0-9]*' "$work/$t.log" | tail -1)
      echo "fuzz_$t: ${runs:-?} inputs in ${seconds} s, ${cov:-cov: ?}, no finding"
    else
      failed+=("$t")
    fi
  done
done

for t in "${failed[@]}"; do
  echo "fuzz_$t: FINDING"
  tail -n 60 "$work/$t.log"
  for f in "$work"/finding-"$t"-*; do  # finding-<target>-{crash,timeout,oom,leak}-<sha1>
    [ -e "$f" ] || continue
    echo "input $(basename "$f") ($(stat -c %s "$f") bytes), base64:"
    base64 "$f"
  done
done
[ ${#failed[@]} -eq 0 ]

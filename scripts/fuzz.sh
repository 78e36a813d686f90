#!/usr/bin/env bash
# Fuzzes the term parser, the clarify request path and the reading of directives in words with cargo-fuzz (libFuzzer), each target for
# a bounded time, starting from the committed seeds and whatever fuzz/corpus/ kept from earlier
# runs. Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 60; use hours for a long hunt)
# Exits nonzero when any target crashes (a panic is a crash) or hangs past libFuzzer's timeout;
# the input that did it is kept under fuzz/artifacts/<target>/ for `cargo fuzz run <target> FILE`.
# Stable Rust is enough: without a sanitizer, cargo-fuzz needs no nightly flags.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz: SECONDS_PER_TARGET must be a positive integer" >&2; exit 2; }
targets=(term_parser clarify_request directive_words)

if ! cargo fuzz --version >/dev/null 2>&1; then
  echo "fuzz: installing cargo-fuzz"
  cargo install cargo-fuzz --locked
fi
# fuzz/ is its own workspace with its own target dir; a CARGO_TARGET_DIR meant for the main
# crate would mix instrumented and plain builds.
unset CARGO_TARGET_DIR
# Built once up front, so that the build does not eat into the first target's time.
cargo fuzz build --sanitizer none

root=$(pwd)
failed=()
for target in "${targets[@]}"; do
  mkdir -p "fuzz/corpus/$target" "fuzz/artifacts/$target"
  # Beside, not inside, the artifacts dir: cargo-fuzz lists everything in there as a crash.
  log="fuzz/artifacts/$target.log"
  started=$(date +%s)
  status=0
  # The first corpus dir receives new inputs; the seeds are read only. -timeout is per input:
  # the clarify target caps each decision at 1 s, so 10 s means a real hang.
  cargo fuzz run --sanitizer none "$target" "$root/fuzz/corpus/$target" "$root/fuzz/seeds/$target" -- \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -dict="$root/fuzz/$target.dict" >"$log" 2>&1 || status=$?
  elapsed=$(( $(date +%s) - started ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
  rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -n 1)
  fuzzed=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -n 1)
  corpus=$(find "fuzz/corpus/$target" -type f | wc -l)
  if [ "$status" -ne 0 ] || grep -qE '^==[0-9]+== ERROR|^SUMMARY: libFuzzer|panicked at|deadly signal' "$log"; then
    failed+=("$target")
    echo "fuzz: FAIL: $target (exit $status) after ${elapsed}s; log $log:" >&2
    grep -E 'panicked at|ERROR|SUMMARY|Test unit written|artifact' "$log" | head -n 20 >&2 || tail -n 30 "$log" >&2
  else
    echo "fuzz: ok: $target: ${execs:-?} executions in ${fuzzed:-?}s of fuzzing, ${elapsed}s wall (${rate:-?} exec/s, peak RSS ${rss:-?} MB, corpus $corpus files)"
  fi
done
if [ "${#failed[@]}" -gt 0 ]; then
  echo "fuzz: ${#failed[@]} target(s) failed: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} targets, no crash or hang in ${seconds}s each"

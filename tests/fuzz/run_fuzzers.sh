#!/usr/bin/env bash
# Runs every libFuzzer harness in BUILD/tests/fuzz (or only those named after SECONDS) for SECONDS each, starting from its seeds
# (tests/fuzz/seeds.txt) and the corpus earlier runs grew (BUILD/fuzz-corpus, kept between runs).
# Prints one line per harness as it ends: executions, coverage, corpus, time. A crash, a leak, a
# timeout or an out-of-memory is told with the reproducer's path, and the script exits failing.
set -uo pipefail
build="$1"
seconds="$2"
shift 2
only=" $* "
root="$(cd "$(dirname "$0")/../.." && pwd)"
# Harnesses run side by side, one per core (IKEBANA_FUZZ_JOBS overrides): each is single-threaded.
jobs_max="${IKEBANA_FUZZ_JOBS:-$(nproc)}"
results="$build/fuzz-findings/results"
rm -rf "$results"
mkdir -p "$results"
printf '%-16s %12s %8s %8s %8s %s\n' harness executions cov features corpus seconds

run_one() {
  local name="$1" sources="$2"
  local binary="$build/tests/fuzz/fuzz_$name"
  local corpus="$build/fuzz-corpus/$name"
  local artifacts="$build/fuzz-findings/$name/"
  mkdir -p "$corpus" "$artifacts"
  local seeds=() s
  for s in $sources; do
    # libFuzzer takes folders: a seed that is a single file is copied into the corpus.
    if [ -d "$root/$s" ]; then seeds+=("$root/$s"); else cp "$root/$s" "$corpus/"; fi
  done
  local log="$build/fuzz-findings/$name.log"
  local start end rc execs cov ft corp
  start=$(date +%s)
  "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$artifacts" "$corpus" "${seeds[@]}" >"$log" 2>&1
  rc=$?
  end=$(date +%s)
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  corp=$(grep -o 'corp: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  printf '%-16s %12s %8s %8s %8s %s\n' "$name" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$((end - start))"
  if [ $rc -ne 0 ]; then
    {
      echo "fuzz_$name found a problem (exit $rc); its log: $log"
      grep -E 'ERROR|SUMMARY|Test unit written|refusal' "$log" | head -5
    } >&2
    echo failed >"$results/$name"
  else
    echo passed >"$results/$name"
  fi
}

running=0
while read -r name sources; do
  case "$name" in ''|'#'*) continue ;; esac
  if [ "$only" != "  " ] && [[ "$only" != *" $name "* ]]; then continue; fi
  if [ "$running" -ge "$jobs_max" ]; then
    wait -n
    running=$((running - 1))
  fi
  run_one "$name" "$sources" &
  running=$((running + 1))
done < "$root/tests/fuzz/seeds.txt"
wait
passed=$(grep -lx passed "$results"/* 2>/dev/null | wc -l)
failed=$(grep -lx failed "$results"/* 2>/dev/null | wc -l)
status=0
[ "$failed" -eq 0 ] || status=1
echo "fuzz: $passed passed, $failed failed"
exit $status

#!/usr/bin/env bash
# Runs every libFuzzer harness in BUILD/tests/fuzz (or only those named after SECONDS) for SECONDS each, starting from its seeds
# (tests/fuzz/seeds.txt) and the corpus earlier runs grew (BUILD/fuzz-corpus, kept between runs).
# Prints one line per harness: executions, coverage, corpus, time. A crash, a leak, a timeout or an
# out-of-memory stops with the reproducer's path and a failing exit.
set -uo pipefail
build="$1"
seconds="$2"
shift 2
only=" $* "
root="$(cd "$(dirname "$0")/../.." && pwd)"
status=0
passed=0
failed=0
printf '%-16s %12s %8s %8s %8s %s\n' harness executions cov features corpus seconds
while read -r name sources; do
  case "$name" in ''|'#'*) continue ;; esac
  if [ "$only" != "  " ] && [[ "$only" != *" $name "* ]]; then continue; fi
  binary="$build/tests/fuzz/fuzz_$name"
  corpus="$build/fuzz-corpus/$name"
  artifacts="$build/fuzz-findings/$name/"
  mkdir -p "$corpus" "$artifacts"
  seeds=()
  for s in $sources; do
    # libFuzzer takes folders: a seed that is a single file is copied into the corpus.
    if [ -d "$root/$s" ]; then seeds+=("$root/$s"); else cp "$root/$s" "$corpus/"; fi
  done
  log="$build/fuzz-findings/$name.log"
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
    echo "fuzz_$name found a problem (exit $rc); its log: $log" >&2
    grep -E 'ERROR|SUMMARY|Test unit written|refusal' "$log" | head -5 >&2
    status=1
    failed=$((failed + 1))
  else
    passed=$((passed + 1))
  fi
done < "$root/tests/fuzz/seeds.txt"
echo "fuzz: $passed passed, $failed failed"
exit $status

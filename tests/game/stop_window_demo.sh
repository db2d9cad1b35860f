#!/bin/bash
# Issue 41: `lesson demo --window` stopped by a signal (Ctrl-C, a timeout) says which step it was at
# and ends the window it drove. Run under xvfb-run. Usage: stop_window_demo.sh IKEBANA WORKDIR
set -u
ikebana=$1 out=$2
rm -rf "$out" && mkdir -p "$out" || exit 1
"$ikebana" lesson demo sogetsu_basic_upright --window --no-history 2> "$out/err" > "$out/out" &
pid=$!
sleep 20
kill -INT "$pid"
wait "$pid"
rc=$?
sleep 2
failures=0
[ "$rc" = 130 ] || { echo "FAIL: exit $rc after SIGINT, expected 130"; failures=1; }
grep -qE "^ikebana lesson demo: stopped at step [0-9]+ of [0-9]+, [0-9]+ s in: " "$out/err" || { echo "FAIL: it does not say where it stopped:"; cat "$out/err"; failures=1; }
grep -qE "^\[[0-9]+/[0-9]+\] shin: take the" "$out/err" || { echo "FAIL: no progress lines:"; cat "$out/err"; failures=1; }
if pgrep -f -- "--state-out .*ikebana-demo-$pid/" >/dev/null; then echo "FAIL: the window it drove is still running"; failures=1; fi
[ "$failures" = 0 ] && echo "stopped, said where, and the window is gone"
exit "$failures"

#!/usr/bin/env bash
# A trainee's journey with the mouse, under xvfb-run: the start screen (a flat screen the first time;
# the side-by-side display chosen there, and remembered at the next start), a lesson picked and started
# there, the hand moved and the camera turned, scored (Enter), back to the start screen (the panel's
# button), the result listed there and in `ikebana history --json`, the session replayed from the
# start screen and back, then Quit; the recording then replays headless to the same score and state. The buttons are found where the window's state file says they
# are (`--state-out`), as a person finds them on the screen. Usage: start_screen_journey.sh IKEBANA WORK
set -euo pipefail
ikebana="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"
export XDG_DATA_HOME="$work/data" XDG_STATE_HOME="$work/state"
state="$work/window.json"
log="$work/app.log"

fail() {
  echo "start screen journey: $*" >&2
  echo "--- the app said:" >&2
  cat "$log" >&2 || true
  exit 1
}

"$ikebana" --trainee "Mika Sato" --width 1200 --height 675 --state-out "$state" >"$log" 2>&1 &
app=$!
trap 'kill $app 2>/dev/null || true' EXIT

# Waits until the state file holds the text (the window has drawn what is looked for).
wait_for() {
  for _ in $(seq 1 1200); do # 2 minutes: under a loaded machine (CI beside another Xvfb session) going back to the start screen took over 60 s once
    if [ -f "$state" ] && grep -q -- "$1" "$state"; then return 0; fi
    kill -0 $app 2>/dev/null || fail "the app ended while waiting for $1"
    sleep 0.1
  done
  fail "the window never showed $1"
}

# Clicks the middle of the button with this label.
click() {
  wait_for "\"label\":\"$1\""
  local box
  # The numbers after the label only: a label's own digits ("speed:x8") were read as the box's first.
  box=$(grep -o "\"label\":\"$1\",\"max_px\":\[[0-9.]*,[0-9.]*\],\"min_px\":\[[0-9.]*,[0-9.]*\]" "$state" | head -1 | sed 's/.*"max_px"://' | grep -o '[0-9.]\+' | tr '\n' ' ')
  read -r x1 y1 x0 y0 <<<"$box"
  [ -n "$y0" ] || fail "no box for the button $1 in the window's state"
  local x=$(( (${x0%.*} + ${x1%.*}) / 2 )) y=$(( (${y0%.*} + ${y1%.*}) / 2 ))
  xdotool mousemove "$x" "$y"
  sleep 0.3
  xdotool mousedown 1
  sleep 0.3
  xdotool mouseup 1
  sleep 0.5
}

presses=0
wait_for '"screen":"start"'
wait_for '"display":"mono"' # a first-time trainee's screen: one view, the whole width
click "display:sbs"; presses=$((presses + 1))
wait_for '"display":"sbs"'
click "select:sogetsu_basic_upright"; presses=$((presses + 1))
click "start:sogetsu_basic_upright"; presses=$((presses + 1))
wait_for '"screen":"lesson"'
# Over the table the hand follows the pointer; the camera turns (Left arrow) and the hand moves again:
# the recording has to carry the turn for the replay to move the hand the same way.
xdotool mousemove 300 420
for i in $(seq 1 15); do xdotool mousemove_relative 6 -3; sleep 0.05; done
xdotool keydown Left; sleep 0.5; xdotool keyup Left
for i in $(seq 1 15); do xdotool mousemove_relative -- -4 2; sleep 0.05; done
sleep 0.5
click "finish"; presses=$((presses + 1))
wait_for '"results":1'
click "back"; presses=$((presses + 1))
wait_for '"screen":"start"'
wait_for '"label":"result:sogetsu_basic_upright: last '
wait_for '"label":"replay:sogetsu_basic_upright"'
# Side by side, each eye's half holds the whole start screen: no button runs past its edge.
python3 - "$state" <<'PY' || fail "a start screen button runs past the eye's half"
import json, sys
s = json.load(open(sys.argv[1]))
half = s["window_px"][0] / 2
bad = [b["label"] for b in s["buttons"] if b["max_px"][0] > half + 0.5]
if bad:
    sys.exit("past %.0f px: %s" % (half, bad))
PY
# The session just finished, watched again from the start screen, and back.
click "replay:sogetsu_basic_upright"; presses=$((presses + 1))
wait_for '"screen":"replay"'
wait_for '"name":"replay"'
# The replay's column is beside the scene, in each eye's half: no panel covers an eye's view.
python3 - "$state" <<'PY' || fail "the replay's panel covers the scene"
import json, sys
layout = json.load(open(sys.argv[1]))["layout"]
def overlap(a, b):
    ax, ay, aw, ah = a["rect_px"]
    bx, by, bw, bh = b["rect_px"]
    return min(ax + aw, bx + bw) - max(ax, bx) > 0.5 and min(ay + ah, by + bh) - max(ay, by) > 0.5
bad = [(p["name"], v["name"], v["eye"]) for p in layout["panels"] for v in layout["views"] + layout["scene"] if overlap(p, v)]
if not layout["views"] or bad:
    sys.exit("covered: %s (views: %d)" % (bad, len(layout["views"])))
PY
click "speed:x8"; presses=$((presses + 1))
wait_for '"results":1'
click "back"; presses=$((presses + 1))
wait_for '"screen":"start"'
click "quit"; presses=$((presses + 1))
for _ in $(seq 1 100); do kill -0 $app 2>/dev/null || break; sleep 0.1; done
kill -0 $app 2>/dev/null && fail "Quit did not end the app"
wait $app || fail "the app ended with an error"
trap - EXIT

grep -q "ikebana: stored as session 1 in $XDG_DATA_HOME/ikebana/progress.sqlite" "$log" || fail "the scored session was not stored"
history=$("$ikebana" history --json)
echo "$history" | grep -q '"trainee": "Mika Sato"' || fail "history does not list Mika Sato's session: $history"
echo "$history" | grep -q '"lesson": "sogetsu_basic_upright"' || fail "history does not list the lesson: $history"
echo "$history" | grep -q '"kind": "practice"' || fail "the session is not practice: $history"
# The score the window showed is the one stored, rounded the one way everything rounds it (a tenth).
shown=$(grep -o 'RESULT: [0-9.]* / 100' "$log" | head -1 | grep -o '[0-9.]\+' | head -1)
stored=$(echo "$history" | grep -o '"score": [0-9.]*' | head -1 | grep -o '[0-9.]\+$')
[ -n "$shown" ] && [ -n "$stored" ] || fail "no score shown ($shown) or stored ($stored)"
[ "$(printf '%.1f' "$stored")" = "$shown" ] || fail "the window showed $shown / 100, the history stores $stored"
# The window's session replays headless to the score and the simulation's state it ended with.
recording=$(echo "$history" | grep -o '"recording": "[^"]*"' | head -1 | sed 's/"recording": "//; s/"$//')
[ -f "$recording/session.json" ] || fail "the stored session has no recording ($recording)"
grep -q ',view,0,' "$recording/commands.csv" || fail "the camera's turn is not on record: $(cat "$recording/commands.csv")"
"$ikebana" replay "$recording" --json "$work/replay.json" >"$work/replay.log" 2>&1 || fail "the replay did not reach the session: $(cat "$work/replay.log")"
grep -q "(as recorded)" "$work/replay.log" || fail "the replay's state hash: $(cat "$work/replay.log")"
grep -q "RESULT: $shown / 100" "$work/replay.log" || fail "the replay scores otherwise than the window's $shown: $(cat "$work/replay.log")"
grep -q "wake lateness" "$log" && fail "the app's terminal shows the threads' figures (they belong in the log or --stats)"
grep -q "wake lateness" "$XDG_STATE_HOME/ikebana/last-session.log" || fail "the session's figures are not in the log"
# The display chosen is the one the next start opens with.
rm -f "$state"
log="$work/app2.log"
"$ikebana" --width 1200 --height 675 --state-out "$state" >"$log" 2>&1 &
app=$!
trap 'kill $app 2>/dev/null || true' EXIT
wait_for '"screen":"start"'
wait_for '"display":"sbs"'
click "quit"
for _ in $(seq 1 100); do kill -0 $app 2>/dev/null || break; sleep 0.1; done
kill -0 $app 2>/dev/null && fail "Quit did not end the app the second time"
wait $app || fail "the app ended with an error the second time"
trap - EXIT
echo "start screen -> lesson -> score -> start screen -> replay -> start screen -> quit: $presses presses"

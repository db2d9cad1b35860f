#!/bin/bash
# The replay window's jumps, timed (docs/progress.md#replay). Run under a display:
#   build/release/game/ikebana lesson demo sogetsu_basic_upright --record /tmp/rec --no-history
#   python3 -c "import json; p='/tmp/rec/session.json'; d=json.load(open(p)); d['end_us']=600000000; json.dump(d, open(p, 'w'))"
#   WAIT=90 xvfb-run -a -s "-screen 0 1280x800x24" tests/bench/replay_seek.sh /tmp/rec
# Opens `ikebana replay REC`, pauses it, waits WAIT seconds (the reading ahead), then clicks the slider
# at about 123 s, 586 s, 123 s, 300 s and 10 s of 600; for each, the time from the click until the
# window shows where it went (read from --state-out).
set -u
ikebana=${IKEBANA:-build/release/game/ikebana}
work=$(mktemp -d)
"$ikebana" replay "$1" --width 1280 --height 720 --state-out "$work/state.json" >"$work/replay.log" 2>&1 &
app=$!
trap 'kill $app 2>/dev/null; rm -rf "$work"' EXIT
sleep 3
STATE="$work/state.json" WAIT="${WAIT:-90}" python3 - <<'PY'
import json, os, subprocess, time
state = os.environ["STATE"]
def read():
    for _ in range(100):
        try:
            return json.load(open(state))
        except Exception:
            time.sleep(0.05)
    raise SystemExit("no window state in " + state)
def button(label):
    return {b["label"]: b for b in read()["buttons"]}[label]
def click(x, y):
    subprocess.run(["xdotool", "mousemove", str(int(x)), str(int(y)), "click", "1"], check=True)
play = button("play")
click((play["min_px"][0] + play["max_px"][0]) / 2, (play["min_px"][1] + play["max_px"][1]) / 2)  # pause
time.sleep(float(os.environ["WAIT"]))
bar = button("timeline")
x0, x1 = bar["min_px"][0], bar["max_px"][0]
y = (bar["min_px"][1] + bar["max_px"][1]) / 2
end_s = 600.0
for target in [123.0, 586.0, 123.0, 300.0, 10.0]:
    before = read()["sim_time_us"]
    click(x0 + (x1 - x0) * target / end_s, y)
    t = time.time(); changed = t; now = before
    while time.time() - t < 120:
        cur = read()["sim_time_us"]
        if cur != now:
            now, changed = cur, time.time()
        if now != before and time.time() - changed > 1.0:
            break
        time.sleep(0.02)
    print(f"jump from {before * 1e-6:.1f} s to {now * 1e-6:.1f} s: {changed - t:.2f} s")
PY

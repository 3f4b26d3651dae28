#!/bin/sh
# The trainer window's screens driven by real key presses (XTEST through xdotool) under a
# virtual X server. Usage: train_screens.sh COLOSIM XVFB_RUN CASE   (needs xdotool, python3)
#   start      the start screen appears; Down Right Enter chooses sigmoid_push in the
#              right lateral position; the session records both and replays bit-identically
#   pause      P pauses for ~1.3 s: no step between the paused and resumed events; R restarts
#              into a new session; both sessions replay bit-identically
#   score_card Escape ends an autopilot free_insertion session: the score card's numbers
#              equal colosim score --json of the recorded session, the expert's those of
#              the shipped references
set -eu
exe=$1
xvfb=$2
case=$3
dir=$(mktemp -d "${TMPDIR:-/tmp}/colosim-train-$case-XXXXXX")
[ -n "${KEEP:-}" ] || trap 'rm -rf "$dir"' EXIT
fail() { echo "train_screens $case: $*" >&2; exit 1; }
assets=$(dirname "$0")/../../assets

# Key presses (the window takes press events; the driving keys are polled held states).
cat >"$dir/press.sh" <<'INNER'
for k in "$@"; do xdotool keydown "$k"; sleep 0.1; xdotool keyup "$k"; sleep 0.2; done
INNER

case $case in
start)
  cat >"$dir/drive.sh" <<INNER
set -eu
"$exe" train --record "$dir/s.jsonl" --quit-after 60 --json >"$dir/out.json" &
pid=\$!
xdotool search --sync --name "colosim train" >/dev/null
sleep 0.5
sh "$dir/press.sh" Down Right Return
sleep 1.5
sh "$dir/press.sh" Escape q
wait "\$pid"
INNER
  ;;
pause)
  cat >"$dir/drive.sh" <<INNER
set -eu
"$exe" train sigmoid_untwist --record "$dir/s.jsonl" --quit-after 60 --json >"$dir/out.json" &
pid=\$!
xdotool search --sync --name "colosim train" >/dev/null
sleep 0.5
sh "$dir/press.sh" p
sleep 1.2
sh "$dir/press.sh" p
sleep 0.3
sh "$dir/press.sh" r
sleep 0.5
sh "$dir/press.sh" Escape q
wait "\$pid"
INNER
  ;;
score_card)
  cat >"$dir/drive.sh" <<INNER
set -eu
"$exe" train free_insertion --autopilot --record "$dir/s.jsonl" --quit-after 60 --screenshot "$dir/card.png" \
  --json >"$dir/out.json" &
pid=\$!
xdotool search --sync --name "colosim train" >/dev/null
sleep 3
sh "$dir/press.sh" Escape
sleep 0.3
sh "$dir/press.sh" q
wait "\$pid"
INNER
  ;;
*) fail "unknown case" ;;
esac

"$xvfb" -a -s "-screen 0 1280x1024x24" sh "$dir/drive.sh" || fail "colosim train exited with $?"
cat "$dir/out.json"

check() { python3 - "$@" || fail "check failed"; }
case $case in
start)
  check "$dir" <<'PY'
import json, sys
d = sys.argv[1]
out = json.load(open(d + "/out.json"))
header = json.loads(open(d + "/s.jsonl").readline())
assert out["screens"] == ["start", "session", "score_card"], out["screens"]
assert out["scenario"] == "sigmoid_push", out["scenario"]
assert out["patient_position"] == "right_lateral", out["patient_position"]
assert header["scenario"] == "sigmoid_push" and header["patient_position"] == "right_lateral", header
# Gravity acts at every step: a replay in another position would not reproduce the hash.
assert out["steps"] > 100 and out["ended_by"] == "end", (out["steps"], out["ended_by"])
PY
  "$exe" replay "$dir/s.jsonl" --check || fail "the session does not replay bit-identically"
  ;;
pause)
  [ -f "$dir/s-2.jsonl" ] || fail "restart made no second session"
  check "$dir" <<'PY'
import json, sys
d = sys.argv[1]
out = json.load(open(d + "/out.json"))
lines = [json.loads(l) for l in open(d + "/s.jsonl")]
events = [l for l in lines if l["type"] == "event" and l["name"] in ("paused", "resumed")]
assert [e["name"] for e in events] == ["paused", "resumed"], events
assert events[0]["step"] == events[1]["step"], events  # no step while paused
end = lines[-1]
assert end["type"] == "end" and end["summary"]["interactive"]["ended_by"] == "restart", end
assert end["summary"]["interactive"]["paused_s"] > 1.0, end["summary"]["interactive"]
print("paused at step", events[0]["step"], "for", end["summary"]["interactive"]["paused_s"], "s")
assert out["sessions"] == [d + "/s.jsonl", d + "/s-2.jsonl"], out["sessions"]
assert out["ended_by"] == "end", out["ended_by"]
assert out["screens"] == ["session", "session", "score_card"], out["screens"]
PY
  "$exe" replay "$dir/s.jsonl" --check || fail "the paused session does not replay bit-identically"
  "$exe" replay "$dir/s-2.jsonl" --check || fail "the restarted session does not replay bit-identically"
  ;;
score_card)
  [ -s "$dir/card.png" ] || fail "no screenshot"
  "$exe" score "$dir/s.jsonl" --json >"$dir/score.json" || fail "colosim score failed"
  check "$dir" "$assets/sessions/expert/free_insertion.jsonl.gz" <<'PY'
import gzip, json, sys
d, expert_path = sys.argv[1], sys.argv[2]
out = json.load(open(d + "/out.json"))
scored = json.load(open(d + "/score.json"))[0]
scores = scored.get("scores", scored)
# The expert's scores: the end line of the shipped expert session.
with gzip.open(expert_path, "rt") as f:
    for line in f:
        pass
expert = json.loads(line)["summary"]["scores"]
assert out["screens"] == ["session", "score_card"], out["screens"]
assert out["ended_by"] == "end"
card = out["score_card"]
assert len(card) >= 10, card
for row in card:
    k = row["key"]
    if k == "caecum_reached":
        assert row["value"] == (0 if scores["time_to_caecum_s"] is None else 1), row
        continue
    assert row["value"] == scores[k], (k, row["value"], scores[k])
    assert row["expert"] == expert[k], (k, row["expert"], expert[k])
    assert row["band"] in ("green", "amber", "red", "none"), row
# The autopilot pushed the scope in: the card holds measured numbers, not only zeros.
rows = {r["key"]: r for r in card}
assert rows["lumen_visible_pct"]["value"] > 50 and rows["mucosa_visualised_pct"]["value"] > 0, rows
# 3 s of the insertion see a few % of the mucosa against the expert's 92 %: red.
assert rows["mucosa_visualised_pct"]["band"] == "red", rows["mucosa_visualised_pct"]
# The caecum rows carry a band when free_insertion's expert reaches the caecum (red: not
# reached in 3 s), none when it does not (the one patient's scripted run ends 0.18 m short).
want = "red" if expert["time_to_caecum_s"] is not None else "none"
assert rows["caecum_reached"]["band"] == want and rows["time_to_caecum_s"]["band"] == want, rows["caecum_reached"]
print(len(card), "rows equal to colosim score --json; mucosa seen", rows["mucosa_visualised_pct"]["value"], "%")

# The last frame (--screenshot) shows the card: its title bar (ImGui's active title colour,
# 0.16 0.29 0.48) spans the middle of the window's top rows.
import struct, zlib
png = open(d + "/card.png", "rb").read()
assert png[:8] == b"\x89PNG\r\n\x1a\n"
pos, idat, width, height = 8, b"", 0, 0
while pos < len(png):
    length, kind = struct.unpack(">I4s", png[pos:pos + 8])
    body = png[pos + 8:pos + 8 + length]
    if kind == b"IHDR":
        width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        assert depth == 8 and colour == 6, (depth, colour)  # 8-bit RGBA
    elif kind == b"IDAT":
        idat += body
    pos += 12 + length
raw, stride, rows_px, prev = zlib.decompress(idat), width * 4, [], bytearray(width * 4)
for y in range(min(height, 60)):  # only the top rows are looked at
    f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - 4] if i >= 4 else 0
        b, c = prev[i], (prev[i - 4] if i >= 4 else 0)
        p = a + b - c
        pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else b if abs(p - b) <= abs(p - c) else c][f]
        line[i] = (line[i] + pred) & 255
    rows_px.append(line)
    prev = line
def px(x, y):
    return tuple(rows_px[y][4 * x:4 * x + 3])
title = [y for y in range(0, 60) if all(abs(u - v) <= 12 for u, v in zip(px(width // 2, y), (41, 74, 122)))]
assert len(title) >= 10, ("no score card title bar in the last frame", [px(width // 2, y) for y in range(0, 60, 5)])
print("score card title bar on rows", title[0], "-", title[-1])
PY
  ;;
esac
echo "train_screens $case: ok"

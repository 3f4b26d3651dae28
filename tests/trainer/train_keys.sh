#!/bin/sh
# Keyboard test of `colosim train` under a virtual X server: hold W (push) for a second
# with xdotool while the window runs, then the session must show the scope pushed in by
# about 3 cm/s x the time held, and replay bit-identically.
# Usage: train_keys.sh COLOSIM XVFB_RUN   (needs xdotool)
set -eu
exe=$1
xvfb=$2
dir=$(mktemp -d "${TMPDIR:-/tmp}/colosim-train-keys-XXXXXX")
trap 'rm -rf "$dir"' EXIT
fail() { echo "train_keys: $*" >&2; exit 1; }

cat >"$dir/drive.sh" <<'INNER'
#!/bin/sh
set -eu
exe=$1; dir=$2
"$exe" train free_insertion --quit-after 6 --record "$dir/keys.jsonl" --json >"$dir/out.json" &
pid=$!
win=$(xdotool search --sync --name "colosim train")
xdotool mousemove --window "$win" 200 200
sleep 1
xdotool keydown w
sleep 1
xdotool keyup w
wait "$pid"
INNER
"$xvfb" -a -s "-screen 0 1280x1024x24" sh "$dir/drive.sh" "$exe" "$dir" || fail "colosim train exited with $?"
cat "$dir/out.json"
insertion=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['scores']['insertion_path_m'])" \
  "$dir/out.json")
echo "insertion path while W was held for ~1 s: $insertion m"
# 3 cm/s for about a second (the key's press and release are seen at frame times).
python3 -c "import sys; v=float(sys.argv[1]); sys.exit(0 if 0.01 < v < 0.06 else 1)" "$insertion" ||
  fail "insertion path $insertion m, expected about 0.03 m"
"$exe" replay "$dir/keys.jsonl" --check || fail "the keyboard session does not replay bit-identically"
echo "train_keys: ok"

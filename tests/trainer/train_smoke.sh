#!/bin/sh
# GLFW smoke test of `colosim train` (run under xvfb-run by ctest): a few seconds of the
# window with the scenario's script driving the handle, then the session written without
# being asked must exist, be complete, have moved the scope, and replay bit-identically.
# Usage: train_smoke.sh COLOSIM XVFB_RUN [SECONDS]
set -eu
exe=$1
xvfb=$2
seconds=${3:-3}
dir=$(mktemp -d "${TMPDIR:-/tmp}/colosim-train-smoke-XXXXXX")
trap 'rm -rf "$dir"' EXIT
fail() { echo "train_smoke: $*" >&2; exit 1; }

"$xvfb" -a -s "-screen 0 1280x1024x24" \
  "$exe" train free_insertion --autopilot --quit-after "$seconds" --record-dir "$dir/sessions" --json \
  >"$dir/out.json" || fail "colosim train exited with $?"
cat "$dir/out.json"
[ "$(ls "$dir/sessions" | wc -l)" -eq 1 ] || fail "expected one session file in $dir/sessions"
session=$(ls "$dir"/sessions/*.jsonl)
case "$(basename "$session")" in
  [0-9][0-9][0-9][0-9][0-9][0-9][0-9][0-9]-[0-9][0-9][0-9][0-9][0-9][0-9]_free_insertion.jsonl) ;;
  *) fail "unexpected session file name $(basename "$session")" ;;
esac
grep -q '"mode":"interactive"' "$session" || fail "the header does not say interactive"
tail -n 1 "$session" | grep -q '"type":"end"' || fail "no end line"
# The autopilot pushes the scope in from the first second: the input changes step after step.
[ "$(grep -c '"type":"input"' "$session")" -gt 100 ] || fail "the handle did not move"
grep -q '"physics_steps_per_s"' "$dir/out.json" || fail "no physics rate in --json"
grep -q '"frames_per_s"' "$dir/out.json" || fail "no frame rate in --json"
"$exe" replay "$session" --check || fail "the session does not replay bit-identically"
# An explicit --record never overwrites: bad input (exit 2), the file untouched.
before=$(cksum <"$session")
set +e
"$exe" train free_insertion --quit-after 0.5 --record "$session" 2>"$dir/err.txt"
code=$?
set -e
[ "$code" -eq 2 ] || fail "--record onto an existing file: exit $code, expected 2"
grep -q "exists" "$dir/err.txt" || fail "no message naming the existing file"
[ "$(cksum <"$session")" = "$before" ] || fail "--record changed an existing file"
echo "train_smoke: ok"

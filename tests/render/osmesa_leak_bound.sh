#!/bin/sh
# Under the sanitizers: the one LSan suppression (scripts/lsan.supp, the whole libOSMesa
# module, since Mesa's frames carry no names) must hide no more than Mesa's own leftovers
# of one context (480 bytes in 5 allocations measured; bound 1024 bytes). A render test runs
# with print_suppressions=1 and the bytes LSan reports as suppressed are checked.
# Usage: osmesa_leak_bound.sh RENDER_TESTS LSAN_SUPP
set -eu
exe=$1
supp=$2
out=$(LSAN_OPTIONS="suppressions=$supp:print_suppressions=1" "$exe" --gtest_filter='RenderTest.PngExport*' 2>&1) ||
  { echo "$out"; echo "osmesa_leak_bound: the render test failed" >&2; exit 1; }
bytes=$(printf '%s\n' "$out" | awk '/Suppressions used:/ {on = 1; next} on && $3 ~ /libOSMesa/ {b += $2} END {print b + 0}')
echo "suppressed by leak:libOSMesa.so: $bytes bytes"
[ "$bytes" -gt 0 ] || { echo "osmesa_leak_bound: no suppressed OSMesa leak reported (is LSan on?)" >&2; exit 1; }
[ "$bytes" -le 1024 ] || { echo "osmesa_leak_bound: $bytes bytes suppressed, more than Mesa's ~480" >&2; exit 1; }

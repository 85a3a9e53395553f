#!/usr/bin/env bash
# Two `study validate --quick` started at once on one cache: both succeed with the same steps.csv,
# each FE entry is solved once (the "solved" progress lines of both logs add up to the entries),
# and no temporary folder or lock file is left in the cache.
#   shared_cache.sh HIPFAI TMP
set -u
hipfai="$1"; tmp="$2"
rm -rf "$tmp"; mkdir -p "$tmp"
"$hipfai" study validate --quick --out "$tmp/a" --cache "$tmp/cache" > "$tmp/a.log" 2>&1 &
a=$!
"$hipfai" study validate --quick --out "$tmp/b" --cache "$tmp/cache" > "$tmp/b.log" 2>&1 &
b=$!
wait "$a"; status_a=$?
wait "$b"; status_b=$?
if [ "$status_a" -ne 0 ] || [ "$status_b" -ne 0 ]; then
  echo "FAIL: exit status $status_a and $status_b"; tail -3 "$tmp/a.log" "$tmp/b.log"; exit 1
fi
cmp -s "$tmp/a/steps.csv" "$tmp/b/steps.csv" || { echo "FAIL: the two steps.csv differ"; exit 1; }
entries=$(find "$tmp/cache/fe" -mindepth 1 -maxdepth 1 -type d | wc -l)
solved=$(grep -h "FE \[[0-9]*/[0-9]*\] .* solved in" "$tmp/a.log" "$tmp/b.log" | wc -l)
leftovers=$(find "$tmp/cache" -name '*.partial' -o -name '*.lock' | wc -l)
echo "FE entries $entries, solved $solved times over both jobs, leftovers $leftovers"
[ "$entries" -eq 2 ] || { echo "FAIL: expected 2 FE entries"; exit 1; }
[ "$solved" -eq "$entries" ] || { echo "FAIL: expected each FE entry solved exactly once over both jobs"; exit 1; }
[ "$leftovers" -eq 0 ] || { echo "FAIL: temporaries or lock files left"; exit 1; }

#!/usr/bin/env bash
# Kill-and-resume: a long command killed with SIGKILL at a random point, then run again, must give
# the results of an uninterrupted run and leave no partial files.
#   kill_resume.sh KIND SEED HIPFAI TMP
# KIND: validate (study validate --quick), fai (study fai --quick), grid (generate --grid, 5 mm),
# sample (estimator sample, 3 + 2 hips at 7 mm).
# The kill comes at a random fraction (20-80 %, from SEED) of the uninterrupted run's time.
set -u
kind="$1"; seed="$2"; hipfai="$3"; tmp="$4"
rm -rf "$tmp"; mkdir -p "$tmp"
run() {  # run DIR: the command writing into DIR/out with its cache in DIR/cache
  case "$kind" in
    validate) "$hipfai" study validate --quick --out "$1/out" --cache "$1/cache" ;;
    fai) "$hipfai" study fai --quick --out "$1/out" --cache "$1/cache" ;;
    grid) "$hipfai" generate --grid --edge-mm 5 --out "$1/out" ;;
    sample) "$hipfai" estimator sample --n 3 --held-out 2 --seed 12 --edge-mm 7 --out "$1/out" ;;
    *) echo "kill_resume: unknown kind $kind" >&2; exit 2 ;;
  esac
}
# Results compared: the tables without timing columns (names ending in _ms or _s), or every file
# of a generated grid.
strip_timing() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) keep[i] = ($i !~ /(_ms|_s)$/) }
           { line = ""; for (i = 1; i <= NF; ++i) if (keep[i]) line = line (line == "" ? "" : ",") $i; print line }' "$1"
}
results() {
  case "$kind" in
    validate) strip_timing "$1/out/steps.csv" ;;
    fai) strip_timing "$1/out/steps.csv"; strip_timing "$1/out/summary.csv" ;;
    grid | sample) (cd "$1/out" && find . -type f | sort | xargs md5sum) ;;
  esac
}
start=$(date +%s%N)
run "$tmp/ref" > "$tmp/ref.log" 2>&1 || { echo "FAIL: the uninterrupted run failed"; tail -5 "$tmp/ref.log"; exit 1; }
ref_ms=$(( ($(date +%s%N) - start) / 1000000 ))
RANDOM=$seed
fraction=$(( 20 + RANDOM % 61 ))
delay_ms=$(( ref_ms * fraction / 100 ))
echo "seed $seed: uninterrupted run $ref_ms ms; SIGKILL after $delay_ms ms ($fraction %)"
# The kill must land while the command runs: a run that finished first (the machine was faster than
# during the reference) is started again with half the delay.
killed=0
for attempt in 1 2 3 4 5 6; do
  rm -rf "$tmp/run"
  setsid bash -c "$(declare -f run); kind=$kind; hipfai=$hipfai; run '$tmp/run'" > "$tmp/killed.log" 2>&1 &
  pid=$!
  sleep "$(awk -v ms="$delay_ms" 'BEGIN { printf "%.3f", ms / 1000 }')"
  if kill -0 "$pid" 2>/dev/null; then
    kill -KILL -- "-$pid" 2>/dev/null || kill -KILL "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    killed=1
    break
  fi
  wait "$pid" 2>/dev/null
  delay_ms=$(( delay_ms / 2 ))
  echo "the run finished before the kill; again with SIGKILL after $delay_ms ms"
done
[ "$killed" = 1 ] || { echo "FAIL: could not interrupt the command (it always finished first)"; exit 1; }
sleep 1  # FE workers die with their parent (PR_SET_PDEATHSIG)
run "$tmp/run" > "$tmp/resumed.log" 2>&1 || { echo "FAIL: the run after the kill failed"; tail -5 "$tmp/resumed.log"; exit 1; }
if ! diff <(results "$tmp/ref") <(results "$tmp/run") > "$tmp/diff.txt"; then
  echo "FAIL: results after kill and resume differ from the uninterrupted run"; head -20 "$tmp/diff.txt"; exit 1
fi
left=$(find "$tmp/run" -name '*.partial*' | head -5)
[ -z "$left" ] || { echo "FAIL: partial files left: $left"; exit 1; }
echo "ok: same results, no partial files"

#!/usr/bin/env bash
# Runs one command-line case: run_cli_test.sh EXPECTED_EXIT STDERR_REGEX -- command args...
# Passes when the exit status equals EXPECTED_EXIT ("nonzero" accepts any failure), stderr
# matches STDERR_REGEX (empty: not checked), and a failing command printed exactly one line.
set -u
expected="$1"; pattern="$2"; shift 2
[ "$1" = "--" ] && shift
err=$(mktemp); out=$(mktemp)
"$@" >"$out" 2>"$err"; status=$?
fail() { echo "FAIL: $*"; echo "--- stdout"; head -c 2000 "$out"; echo "--- stderr"; head -c 2000 "$err"; rm -f "$err" "$out"; exit 1; }
if [ "$expected" = "nonzero" ]; then
  [ "$status" -ne 0 ] || fail "expected a non-zero exit, got 0"
  [ "$(grep -c . "$err")" -eq 1 ] || fail "expected a one-line error on stderr"
else
  [ "$status" -eq "$expected" ] || fail "expected exit $expected, got $status"
fi
if [ -n "$pattern" ]; then grep -Eq -e "$pattern" "$err" || fail "stderr does not match /$pattern/"; fi
rm -f "$err" "$out"
echo "ok"

#!/usr/bin/env bash
# cli_expect.sh CODE PATTERN COMMAND [ARGS...]: runs COMMAND (killed after 60 s: a hang fails)
# and passes when it exits with CODE and its output (stdout and stderr) matches PATTERN (grep -E).
set -u
want=$1 pattern=$2
shift 2
out=$(timeout 60 "$@" 2>&1)
rc=$?
printf '%s\n' "$out"
[ "$rc" -eq "$want" ] || { echo "FAIL: exit code $rc, expected $want"; exit 1; }
grep -qE -- "$pattern" <<<"$out" || { echo "FAIL: the output does not match /$pattern/"; exit 1; }

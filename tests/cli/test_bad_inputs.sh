#!/usr/bin/env bash
# Hostile input: every case in tests/bad_inputs/ must be refused with exit code 2 and exactly
# one message ("mpm_geo: error: ..." naming the case file), never a crash, a backtrace or a
# hang, and must write no output.
# Usage: tests/cli/test_bad_inputs.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0
for case in tests/bad_inputs/*.json; do
    name=$(basename "$case")
    timeout 60 "$exe" "$case" --output "$tmp/out-$name" > "$tmp/stdout" 2> "$tmp/stderr"
    rc=$?
    messages=$(grep -c "^mpm_geo: error:" "$tmp/stderr")
    problem=""
    [ "$rc" -eq 2 ] || problem="exit code $rc, expected 2"
    [ "$messages" -eq 1 ] || problem="$problem; $messages error messages, expected 1"
    grep -q "$case" "$tmp/stderr" || problem="$problem; the message does not name the file"
    if grep -qE "Backtrace|Error termination|Segmentation|SIGSEGV|ERROR STOP" "$tmp/stderr"; then
        problem="$problem; crash report"
    fi
    [ -e "$tmp/out-$name" ] && problem="$problem; an output folder was written"
    if [ -z "$problem" ]; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
        echo "FAIL [bad input] $name: ${problem#; }"
        sed 's/^/    /' "$tmp/stderr" | head -5
    fi
done
echo "$passed passed, $failed failed"
[ "$passed" -ge 40 ] || { echo "FAIL [bad input] fewer than 40 cases"; exit 1; }
[ "$failed" -eq 0 ]

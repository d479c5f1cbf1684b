#!/usr/bin/env bash
# The lock on an output folder (issue 17): a run holds an advisory lock on its output folder
# (.mpm_geo.lock), so a second run into it, even with --overwrite or --restart, is refused
# with exit code 2 naming the folder and the holder, and the first run's files stay as they
# are; --check takes none; the lock dies with the process (kill -9 leaves nothing stale).
# Usage: tests/cli/test_output_lock.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
case_file=tests/cli/cases/restart_collapse.json
tmp=$(mktemp -d)
pid=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2> /dev/null; rm -rf "$tmp"' EXIT
label=lock
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh

# a run far longer than the test (killed below), with a checkpoint every 20 steps
sed 's/"tend": 0.3/"tend": 30.0/' "$case_file" > "$tmp/long.json"
sed 's/"tend": 0.3/"tend": 0.003/' "$case_file" > "$tmp/short.json"
"$exe" "$tmp/long.json" --output "$tmp/a" --quiet --checkpoint-steps 20 > "$tmp/first" 2>&1 &
pid=$!
for _ in $(seq 1 1500); do [ -f "$tmp/a/checkpoint.h5" ] && break; sleep 0.01; done
sum_before=$(md5sum "$tmp/a/particles_000000.h5")

# (timeout: a run that is not refused would go on for long)
expect 2 "a second run into the folder" -- timeout 60 "$exe" "$tmp/short.json" \
    --output "$tmp/a" --overwrite --quiet
contains "output folder '$tmp/a' is in use by another run (pid $pid on host $(uname -n)); wait for it to finish or choose another --output" \
    "a second run into the folder: message"
expect 2 "a restart into the folder" -- timeout 60 "$exe" --restart "$tmp/a/checkpoint.h5" \
    --quiet
contains "is in use by another run (pid $pid" "a restart into the folder: message"
expect 0 "--check of a case whose folder is in use" -- "$exe" "$tmp/short.json" \
    --output "$tmp/a" --overwrite --check
if kill -0 "$pid" 2> /dev/null; then ok; else bad "the first run did not run all along"; cat "$tmp/first"; fi
[ "$(md5sum "$tmp/a/particles_000000.h5")" = "$sum_before" ] && ok ||
    bad "the refused runs changed the first run's files"

# killed: the lock goes with the process
kill -9 "$pid"
wait "$pid" 2> /dev/null
pid=""
expect 0 "a run after the holder was killed" -- "$exe" "$tmp/short.json" --output "$tmp/a" \
    --overwrite --quiet
[ ! -s "$tmp/a/.mpm_geo.lock" ] && ok || bad "a finished run left its record in the lock file"

echo "lock tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]

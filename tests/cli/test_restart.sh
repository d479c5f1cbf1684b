#!/usr/bin/env bash
# Checkpoints and restarts (issue 8): a run stopped by SIGTERM or SIGINT writes a checkpoint
# and exits with code 4 (not with checkpoint.on_signal = false); `mpm_geo --restart FILE`
# (another thread count) and `mpm_geo CASE --restart` continue it, and every output and the energy history are then the same, bit for bit, as
# those of a run that was never stopped; a damaged or wrong checkpoint is refused with exit
# code 2; the blow-up guard stops an unstable run with exit code 3 and saves the last healthy
# state, from which a stable case file continues.
# Usage: tests/cli/test_restart.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
case_file=tests/cli/cases/restart_collapse.json
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
label=restart
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh
need_python numpy h5py
identical() {
    if "$python" tests/cli/compare_identical.py "$1" "$2" > "$tmp/cmp" 2>&1; then ok; else
        bad "$3"; cat "$tmp/cmp"; fi
}
# signal_run SIGNAL FILE -- command...: start the command, send it SIGNAL once FILE exists;
# its exit code in $rc, its output in $tmp/out
signal_run() {
    local signal=$1 file=$2 pid
    shift 3
    "$@" > "$tmp/out" 2>&1 &
    pid=$!
    for _ in $(seq 1 1500); do [ -f "$file" ] && break; sleep 0.01; done
    kill -"$signal" "$pid"
    wait "$pid"
    rc=$?
}

# the run that is never stopped
expect 0 "reference run" -- "$exe" "$case_file" --output "$tmp/a" --quiet

# stopped by SIGTERM once its first checkpoint is there (every 100 steps), as Slurm does at
# the time limit
signal_run TERM "$tmp/b/checkpoint.h5" -- "$exe" "$case_file" --output "$tmp/b" --quiet \
    --checkpoint-steps 100
if [ "$rc" -eq 4 ]; then ok; else bad "SIGTERM: exit code $rc, expected 4"; cat "$tmp/out"; fi
contains "stopped by SIGTERM" "SIGTERM: message"
contains "mpm_geo --restart $tmp/b/checkpoint.h5" "SIGTERM: how to continue"
if [ "$rc" -eq 4 ]; then
    # a write killed half-way leaves a .tmp beside the last good checkpoint: never read
    echo "half a file" > "$tmp/b/checkpoint.h5.tmp"
    OMP_NUM_THREADS=2 expect 0 "restart from the checkpoint (2 threads)" -- \
        "$exe" --restart "$tmp/b/checkpoint.h5" --quiet
    identical "$tmp/a" "$tmp/b" "stopped and restarted run = uninterrupted run"
fi

# SIGINT (Ctrl-C) too; with checkpoint.on_signal = false the default action ends the run
signal_run INT "$tmp/i/checkpoint.h5" -- "$exe" "$case_file" --output "$tmp/i" --quiet \
    --checkpoint-steps 100
if [ "$rc" -eq 4 ]; then ok; else bad "SIGINT: exit code $rc, expected 4"; cat "$tmp/out"; fi
contains "stopped by SIGINT" "SIGINT: message"
sed 's#"progress"#"checkpoint": {"on_signal": false}, "progress"#' "$case_file" > "$tmp/nosig.json"
signal_run TERM "$tmp/n/particles_000001.h5" -- "$exe" "$tmp/nosig.json" --output "$tmp/n" \
    --quiet
if [ "$rc" -eq 143 ] && [ ! -e "$tmp/n/checkpoint.h5" ]; then ok; else
    bad "on_signal = false: exit code $rc (expected 143, killed by SIGTERM) or a checkpoint"; fi

# checkpoints every 500 steps to the end; the case continues from its own checkpoint (the
# last, step 1500 of ~1580): the history lines after it are dropped and written again
expect 0 "run with checkpoints" -- "$exe" "$case_file" --output "$tmp/c" --quiet \
    --checkpoint-steps 500
expect 0 "restart from the case's checkpoint" -- "$exe" "$case_file" --restart \
    --output "$tmp/c" --quiet
identical "$tmp/a" "$tmp/c" "run restarted from its last checkpoint = uninterrupted run"

# the running loads of an STL terrain contact are kept too: a block sliding on a terrain floor
# under tilted gravity (tests/cli/cases/terrain_block.json), restarted from its last checkpoint (step 600 of ~820)
terrain_case=tests/cli/cases/terrain_block.json
expect 0 "terrain reference run" -- "$exe" "$terrain_case" --output "$tmp/ta" --quiet
expect 0 "terrain run with checkpoints" -- "$exe" "$terrain_case" --output "$tmp/tb" \
    --quiet --checkpoint-steps 300
expect 0 "terrain run restarted" -- "$exe" --restart "$tmp/tb/checkpoint.h5" --quiet
identical "$tmp/ta" "$tmp/tb" "terrain run restarted from its last checkpoint = uninterrupted run"

# refusals: exit code 2, one message naming the file
expect 2 "missing checkpoint" -- "$exe" --restart "$tmp/none.h5"
contains "cannot restart from '$tmp/none.h5': the file does not exist" "missing checkpoint"
expect 2 "damaged checkpoint" -- "$exe" --restart "$tmp/b/checkpoint.h5.tmp"
contains "not an HDF5 file" "damaged checkpoint"
expect 2 "an output file is not a checkpoint" -- "$exe" --restart "$tmp/a/particles_000001.h5"
contains "not an mpm-geo state file or checkpoint" "an output file is not a checkpoint"
sed "s#\"progress\"#\"save_state\": \"$tmp/state.h5\", \"progress\"#" "$case_file" \
    | sed 's#"tend": 0.3#"tend": 0.01#' > "$tmp/save.json"
expect 0 "a state file" -- "$exe" "$tmp/save.json" --output "$tmp/s" --quiet
expect 0 "--checkpoint-minutes at the largest double" -- "$exe" "$tmp/save.json" \
    --output "$tmp/m" --checkpoint-minutes 1e308 --quiet
expect 2 "a state file is not a checkpoint" -- "$exe" --restart "$tmp/state.h5"
contains "load_state" "a state file is not a checkpoint: what to do instead"
expect 2 "--restart cannot move the output folder" -- "$exe" --restart \
    "$tmp/c/checkpoint.h5" --output "$tmp/elsewhere"
expect 2 "--restart without a checkpoint or case" -- "$exe" --restart
expect 2 "bad --checkpoint-steps" -- "$exe" "$case_file" --checkpoint-steps 0
contains "--checkpoint-steps 0" "bad --checkpoint-steps: names the option"
expect 2 "bad --checkpoint-minutes" -- "$exe" "$case_file" --checkpoint-minutes nan
expect 2 "--checkpoint-minutes beyond a double" -- "$exe" "$case_file" --checkpoint-minutes 1e999
[ ! -e "$tmp/elsewhere" ] && ok || bad "a refused restart wrote an output folder"

# the blow-up guard: exit 3, step, particle, position, and the last healthy state saved
sed 's#"cfl": 0.4#"cfl": 3.0, "allow_unstable": true#' "$case_file" > "$tmp/unstable.json"
expect 3 "unstable run" -- "$exe" "$tmp/unstable.json" --output "$tmp/u" --quiet
contains "became unstable" "unstable run: why"
contains "particle" "unstable run: which particle"
contains "the last healthy state (step 0," "unstable run: the healthy state"
contains "$tmp/u/last_healthy.h5" "unstable run: where the healthy state is"
expect 0 "continue from the last healthy state with a stable time step" -- \
    "$exe" "$case_file" --restart "$tmp/u/last_healthy.h5" --quiet
identical "$tmp/a" "$tmp/u" "restarted from the healthy state = uninterrupted run"

# --overwrite starts afresh: the earlier run's checkpoints go with its outputs, so that a
# restart cannot continue the earlier run in the new one's folder
expect 0 "a new run over the folder of one with checkpoints" -- "$exe" "$tmp/save.json" \
    --output "$tmp/c" --overwrite --quiet
[ ! -e "$tmp/c/checkpoint.h5" ] && ok || bad "--overwrite kept the earlier run's checkpoint"
expect 0 "a new run over the folder of a run the guard stopped" -- "$exe" "$tmp/save.json" \
    --output "$tmp/u" --overwrite --quiet
[ ! -e "$tmp/u/last_healthy.h5" ] && ok || bad "--overwrite kept the earlier run's healthy state"

# a Kelvin-Voigt base (absorbing face with springs): the checkpoint keeps the springs'
# stretch, so a restart settles as the uninterrupted run does (from zero stretch it would not)
sed 's/"tend": 2.0/"tend": 0.4/; s/"interval": 0.05/"interval": 0.1/' \
    validation/absorbing_base/absorbing_base_static_kv.json > "$tmp/kv.json"
expect 0 "Kelvin-Voigt base: whole run" -- "$exe" "$tmp/kv.json" --output "$tmp/kv_a" --quiet
expect 0 "Kelvin-Voigt base: run with checkpoints" -- "$exe" "$tmp/kv.json" --output \
    "$tmp/kv_b" --checkpoint-steps 1000 --quiet
expect 0 "Kelvin-Voigt base: restart from its last checkpoint" -- "$exe" --restart \
    "$tmp/kv_b/checkpoint.h5" --quiet
identical "$tmp/kv_a" "$tmp/kv_b" "Kelvin-Voigt base: restarted = uninterrupted run"

echo "restart tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]

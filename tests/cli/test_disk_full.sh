#!/usr/bin/env bash
# A full disk (issue 17): a run whose output folder fills up stops with exit code 5 and one
# message that names the file and says "no space left on device" (no HDF5 error stack, no
# crash: HDF5 1.10 used to segfault in its exit handler after a failed close). The .tmp of
# the failed write is gone, the earlier particle files, the XDMF index (which lists only
# complete files), the energy history (whole lines) and the last checkpoint stay whole. The
# blow-up guard's copy of the state (a file in the output folder) on a full disk: the same.
# The full disk is a small tmpfs, which needs root (mount); without it the test is skipped
# (exit code 77, CTest's SKIP_RETURN_CODE).
# Usage: tests/cli/test_disk_full.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
case_file=tests/cli/cases/restart_collapse.json
tmp=$(mktemp -d)
mnt=$tmp/mnt
mkdir -p "$mnt"
cleanup() {
    mountpoint -q "$mnt" && umount "$mnt"
    rm -rf "$tmp"
}
trap cleanup EXIT
label=disk_full
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh

# full_disk SIZE: a fresh tmpfs of SIZE at $mnt
full_disk() {
    mountpoint -q "$mnt" && umount "$mnt"
    mount -t tmpfs -o "size=$1" tmpfs "$mnt" 2> "$tmp/mount.err"
}
need_python numpy h5py
if ! full_disk 160k; then
    if [ "${MPM_STRICT_TESTS:-0}" = 1 ]; then
        echo "FAIL [$label] cannot mount a small tmpfs to fill ($(cat "$tmp/mount.err"))"
        exit 1
    fi
    echo "SKIP: cannot mount a small tmpfs to fill ($(cat "$tmp/mount.err")); this test needs root"
    exit 77
fi

# whole FOLDER: no .tmp left, every file the index lists is a complete HDF5 file and every
# particle file is listed, every line of history.csv has a number for each column of its header
whole() {
    if "$python" - "$1" > "$tmp/whole" 2>&1 <<'PY'; then ok; else bad "$2"; cat "$tmp/whole"; fi
import glob, os, re, sys
import h5py
d = sys.argv[1]
problems = [f"left over: {p}" for p in glob.glob(os.path.join(d, "*.tmp"))]
xdmf = glob.glob(os.path.join(d, "*.xdmf"))
listed = set(re.findall(r"(particles_\d+\.h5):", open(xdmf[0]).read())) if xdmf else set()
present = {os.path.basename(p) for p in glob.glob(os.path.join(d, "particles_*.h5"))}
if not listed:
    problems.append("the index lists no particle file")
problems += [f"listed but missing: {n}" for n in sorted(listed - present)]
for name in sorted(listed & present):
    with h5py.File(os.path.join(d, name), "r") as f:
        n = f["particles/position"].shape[0]
        if n == 0 or not (f["particles/position"][()] == f["particles/position"][()]).all():
            problems.append(f"{name}: no or NaN positions")
lines = open(os.path.join(d, "history.csv")).read().splitlines()
for line in lines[1:]:
    values = line.split(",")
    if len(values) != len(lines[0].split(",")):
        problems.append(f"history.csv: cut line '{line}'")
        continue
    [float(v) for v in values]
print("\n".join(problems))
sys.exit(1 if problems else 0)
PY
}
# fill_at FROM PATTERN COMMAND...: the smallest disk, in pages of 4 kB from FROM kB up, on
# which the command stops on a full disk with a message that contains PATTERN and, when
# $also is set, after which the command $also succeeds (which file fills the disk depends on
# the sizes of the outputs: searched, not written down). Exit code in $rc, output in
# $tmp/out, files on $mnt, the size in $kb; fails the test when no size up to 2 MB does it.
also=""
fill_at() {
    local from=$1 pattern=$2
    shift 2
    for kb in $(seq "$from" 4 2048); do
        full_disk "${kb}k"
        "$@" > "$tmp/out" 2>&1
        rc=$?
        if grep -qF -- "$pattern" "$tmp/out" && grep -qF "no space left on device" "$tmp/out" \
            && { [ -z "$also" ] || eval "$also"; }; then
            return 0
        fi
        # past the size where the run fits whole, no failure will come
        grep -q "no space left on device" "$tmp/out" || break
    done
    bad "no disk size makes the run fail with '$pattern' (last: ${kb}k):"
    cat "$tmp/out"
    return 1
}
# failed_with CODE WHAT: the run of fill_at ended with CODE, and with no crash report
failed_with() {
    if [ "$rc" -eq "$1" ]; then ok; else bad "$2: exit code $rc, expected $1"; cat "$tmp/out"; fi
    if grep -qE "Backtrace|Error termination|Segmentation|SIGSEGV" "$tmp/out"; then
        bad "$2: output holds a crash report"; cat "$tmp/out"
    else
        ok
    fi
}
no_stack() {
    if grep -q "HDF5-DIAG" "$tmp/out"; then bad "$1: the HDF5 error stack reached the user"; else ok; fi
    [ "$(grep -c "error:" "$tmp/out")" -eq 1 ] && ok || { bad "$1: not one message"; cat "$tmp/out"; }
}

# a particle file fills the disk (0.008 s, an output every 0.002 s)
sed 's/"tend": 0.3/"tend": 0.008/; s/"interval": 0.03/"interval": 0.002/' "$case_file" \
    > "$tmp/short.json"
fill_at 64 "particles_000001.h5'" "$exe" "$tmp/short.json" --output "$mnt/o" --quiet
failed_with 5 "particle file on a full disk"
contains "no space left on device" "particle file on a full disk: why"
contains "$mnt/o/particles_000001.h5'" "particle file on a full disk: which file"
no_stack "particle file on a full disk"
whole "$mnt/o" "particle file on a full disk: the outputs before it are whole"

# the index fills it (the particle file fits, its index does not)
fill_at "$kb" "cannot write '$mnt/o/restart_collapse.xdmf'" "$exe" "$tmp/short.json" \
    --output "$mnt/o" --quiet
failed_with 5 "index on a full disk"
contains "cannot write '$mnt/o/restart_collapse.xdmf': no space left on device" \
    "index on a full disk: which file and why"
no_stack "index on a full disk"
whole "$mnt/o" "index on a full disk: the index before it is whole"

# the second checkpoint fills it: the first stays whole and a restart can use it
sed 's/"tend": 0.3/"tend": 0.01/; s/"interval": 0.03/"interval": 1.0/' "$case_file" \
    > "$tmp/checkpoints.json"
also='[ -f "$mnt/o/checkpoint.h5" ]'
fill_at 128 "$mnt/o/checkpoint.h5'" "$exe" "$tmp/checkpoints.json" --output "$mnt/o" \
    --quiet --checkpoint-steps 10
also=""
failed_with 5 "checkpoint on a full disk"
contains "$mnt/o/checkpoint.h5': no space left on device" "checkpoint on a full disk: why"
no_stack "checkpoint on a full disk"
whole "$mnt/o" "checkpoint on a full disk: the outputs are whole"
expect 0 "the last checkpoint is whole" -- "$exe" "$tmp/checkpoints.json" --check --restart \
    "$mnt/o/checkpoint.h5"
contains "(step 10) fits the case" "the last checkpoint is whole: its step"

# the guard's copy of the state (a file of the output folder by default) fills it: the run
# stops with the message of a full disk and says how to keep the copy elsewhere or not at all
sed 's/"tend": 0.3/"tend": 0.01/; s/"interval": 0.03/"interval": 1.0/; s/"progress": {/"guard": {"snapshot_steps": 10}, "progress": {/' \
    "$case_file" > "$tmp/guard.json"
grep -q '"snapshot_steps": 10' "$tmp/guard.json" || bad "could not set guard.snapshot_steps"
fill_at 128 "$mnt/o/.last_healthy.h5" "$exe" "$tmp/guard.json" --output "$mnt/o" --quiet
failed_with 5 "guard's copy on a full disk"
contains "the blow-up guard cannot keep its copy of the state" "guard's copy on a full disk: what"
contains '"snapshot_in": "memory"' "guard's copy on a full disk: the other place"
no_stack "guard's copy on a full disk"
whole "$mnt/o" "guard's copy on a full disk: the outputs are whole"

echo "disk full tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# Runs on 2 images against the serial build (CTest in the coarray build, make test-coarray):
#  - each case of tests/parallel/cases/ (2D and 3D, particles crossing the cut, an image that
#    starts empty, cuts that move with the particles, blocks sliding on an STL terrain across
#    the cut, XPIC and absorbing faces whose nodes lie on both sides of the cut, a traction,
#    a point load and a body force, and a footing of prescribed_motion, across the cut): particle
#    count, ids and masses exactly, positions, velocities and stresses to round-off, the
#    energy history column by column (compare_runs.py);
#  - a state saved on 2 images continues serially, and a serial state on 2 images, as the
#    serial run does;
#  - failures: a broken case file, a particle lost on one image and an STL terrain that misses
#    every slab give the serial exit code and one message;
#  - a checkpoint written on 2 images continues on 2 images as the serial run does (also with
#    the running loads of an STL terrain), and is refused on 1 image;
#  - 3 images (one with neighbours on both sides, one that starts empty) and 2 images of 2
#    threads each (hybrid) give the serial result too;
#  - ParaView (pvbatch) opens the parts of a run as one time series, with both XDMF readers.
# usage: test_images_match_serial.sh CAF_MPM_GEO SERIAL_MPM_GEO CAFRUN
set -uo pipefail
cd "$(dirname "$0")/../.."
caf_exe=$1
serial_exe=$2
cafrun=$3
[ -x "$serial_exe" ] || { echo "FAIL: serial build $serial_exe not found (make build)"; exit 1; }
label=images
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh
need_python numpy h5py
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
export OMP_NUM_THREADS=1

par() { "$cafrun" -np 2 "$caf_exe" "$@"; }

for case in tests/parallel/cases/*.json; do
    name=$(basename "$case" .json)
    "$serial_exe" "$case" --output "$tmp/$name-serial" -q || { fail "$name: serial run"; continue; }
    par "$case" --output "$tmp/$name-images" -q || { fail "$name: run on 2 images"; continue; }
    echo "--- $name"
    # the block starts on image 1 and slides into image 2's slab: the cuts follow it
    min_part=0
    [ "$name" = par_block_moves_2d ] && min_part=4
    # blocks sliding on an STL terrain from the cut into image 2's slab: the terrain pairs of
    # the new slabs take the running loads of their nodes
    case "$name" in par_terrain_slide_*) min_part=40 ;; esac
    "$python" tests/parallel/compare_runs.py "$tmp/$name-serial" "$tmp/$name-images" \
        --min-part "$min_part" || fail "$name: 2 images differ from the serial run"
done

# 3 images (more than the cores: --oversubscribe): the middle image has a neighbour on each
# side and a slab of 3 cells, the last one starts without particles; the nodes a neighbour's
# particles touch are in both images' boxes, so the frictional floor's running loads and the
# energy sums agree with the serial run
for name in par_collapse_3d par_terrain_slide_3d; do
    echo "--- $name on 3 images"
    "$cafrun" -np 3 --oversubscribe "$caf_exe" "tests/parallel/cases/$name.json" \
        --output "$tmp/$name-3images" -q || { fail "$name: run on 3 images"; continue; }
    "$python" tests/parallel/compare_runs.py "$tmp/$name-serial" "$tmp/$name-3images" --images 3 \
        || fail "$name: 3 images differ from the serial run"
done

# Checkpoint and restart on 2 images: the checkpoint gathers every particle in id order with
# the frictional face loads of the whole grid; the run restarted from it (step 1000 of 1280)
# on 2 images gives the serial result (to round-off: the particle order within the images
# is not that of the run before); a restart on another number of images is refused
echo "--- par_collapse_2d: checkpoint at step 1000 on 2 images, restarted on 2 images"
par tests/parallel/cases/par_collapse_2d.json --output "$tmp/ckpt" --checkpoint-steps 1000 -q \
    || fail "run with a checkpoint on 2 images"
par --restart "$tmp/ckpt/checkpoint.h5" -q || fail "restart on 2 images"
"$python" tests/parallel/compare_runs.py "$tmp/par_collapse_2d-serial" "$tmp/ckpt" \
    || fail "a run restarted on 2 images differs from the serial run"
"$serial_exe" --restart "$tmp/ckpt/checkpoint.h5" -q 2> "$tmp/restart1.err"
rc=$?
[ "$rc" -eq 2 ] && grep -q "written by a run on 2 image" "$tmp/restart1.err" \
    || { fail "a checkpoint of 2 images restarted on 1: exit $rc, expected 2"; cat "$tmp/restart1.err"; }

# The running loads of an STL terrain contact in a checkpoint of 2 images (by node of the
# whole grid: the restart cuts the grid anew): step 2400 of 2512, after the cuts moved
echo "--- par_terrain_slide_2d: checkpoint at step 2400 on 2 images, restarted on 2 images"
par tests/parallel/cases/par_terrain_slide_2d.json --output "$tmp/tckpt" --checkpoint-steps 400 \
    -q || fail "terrain run with checkpoints on 2 images"
par --restart "$tmp/tckpt/checkpoint.h5" -q || fail "terrain restart on 2 images"
"$python" tests/parallel/compare_runs.py "$tmp/par_terrain_slide_2d-serial" "$tmp/tckpt" \
    || fail "a terrain run restarted on 2 images differs from the serial run"

# Hybrid: 2 images of 2 threads each (threads do not change the bits of an image's sums)
echo "--- par_collapse_3d on 2 images x 2 threads"
OMP_NUM_THREADS=2 "$cafrun" -np 2 --bind-to none "$caf_exe" tests/parallel/cases/par_collapse_3d.json \
    --output "$tmp/hybrid" -q || fail "hybrid run"
"$python" tests/parallel/compare_runs.py "$tmp/par_collapse_3d-serial" "$tmp/hybrid" \
    || fail "2 images x 2 threads differ from the serial run"

# ParaView opens the parts of a run as one time series, with both of its XDMF readers:
# points and vertex cells of all parts, every array, ids 1..N once, the grid slabs, Threshold
# on material against the HDF5 counts (par_paraview_2d: two materials across the cut, grid
# output), nothing on stderr (pvbatch comes with make test's deps)
if command -v pvbatch > /dev/null 2>&1; then
    echo "--- ParaView: par_paraview_2d and par_collapse_2d on 2 images (Xdmf3ReaderS, XDMFReader)"
    "$python" tests/cli/check_xdmf_paraview.py "$tmp/par_paraview_2d-images/par_paraview_2d.xdmf" \
        "$tmp/par_collapse_2d-images/par_collapse_2d.xdmf" > "$tmp/pv.log" 2>&1
    rc=$?
    echo "$(grep -c "^ok" "$tmp/pv.log") pvbatch checks passed"
    grep -v "^ok" "$tmp/pv.log"
    { [ "$rc" -eq 0 ] \
        && grep -q "^ok   XDMFReader par_collapse_2d.* ids 1..3200, each once" "$tmp/pv.log" \
        && grep -q "^ok   Xdmf3ReaderS par_paraview_2d.* Threshold material = 2 keeps 84" \
            "$tmp/pv.log" \
        && grep -q "^ok   XDMFReader par_paraview_2d.* Threshold material = 2 keeps 84" \
            "$tmp/pv.log"; } \
        || fail "ParaView does not open the parts of a run on 2 images as one series"
elif [ "${MPM_STRICT_TESTS:-0}" = 1 ]; then
    fail "pvbatch not found: the parts are not opened in ParaView (make deps-test installs it)"
else
    echo "--- SKIP ParaView check: pvbatch not found"
fi

# State files across image counts: the collapse saved at 0.08 s, continued to 0.15 s
stage() {   # stage NAME TEND [load|save STATE ...]: writes $tmp/NAME.json
    "$python" - "$tmp" "$@" <<'EOF'
import json, sys
folder, name, tend, rest = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4:]
c = json.load(open("tests/parallel/cases/par_collapse_2d.json"))
c["name"] = name
c["time"]["tend"] = tend
c["output"]["interval"] = 0.05
for key, path in zip(rest[::2], rest[1::2]):
    c[key + "_state"] = path
    if key == "load":
        del c["bodies"]
json.dump(c, open(f"{folder}/{name}.json", "w"))
EOF
}
stage first 0.08 save "$tmp/first.h5"
stage rest 0.07 load "$tmp/first.h5"
stage first2 0.08 save "$tmp/first2.h5"
stage rest2 0.07 load "$tmp/first2.h5"
"$serial_exe" "$tmp/first.json" --output "$tmp/first" -q || fail "state: serial first stage"
"$serial_exe" "$tmp/rest.json" --output "$tmp/rest-serial" -q || fail "state: serial second stage"
par "$tmp/rest.json" --output "$tmp/rest-images" -q || fail "state: second stage on 2 images"
echo "--- serial state continued on 2 images"
"$python" tests/parallel/compare_runs.py "$tmp/rest-serial" "$tmp/rest-images" \
    || fail "a serial state continued on 2 images differs from the serial continuation"
par "$tmp/first2.json" --output "$tmp/first2" -q || fail "state: first stage on 2 images"
"$serial_exe" "$tmp/rest2.json" --output "$tmp/rest2-serial" -q \
    || fail "state: serial run from a state saved on 2 images"
echo "--- state saved on 2 images, continued serially"
"$python" - "$tmp/first.h5" "$tmp/first2.h5" <<'EOF' || fail "states saved serially and on 2 images differ"
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
def walk(g, prefix=""):
    for k, v in g.items():
        if isinstance(v, h5py.Group):
            yield from walk(v, prefix + k + "/")
        else:
            yield prefix + k, v[()]
da, db = dict(walk(a)), dict(walk(b))
assert da.keys() == db.keys(), (sorted(da), sorted(db))
worst = 0.0
for k in da:
    x, y = np.asarray(da[k]), np.asarray(db[k])
    assert x.shape == y.shape, (k, x.shape, y.shape)
    if x.dtype.kind in "iu":
        assert np.array_equal(x, y), k
    else:
        worst = max(worst, float(np.abs(x - y).max() / max(np.abs(x).max(), 1e-300)))
print(f"state files: same datasets and shapes, largest relative difference {worst:.2e}")
assert worst < 1e-9
EOF
"$python" tests/parallel/compare_runs.py "$tmp/rest-serial" "$tmp/rest2-serial" --images 1 \
    || fail "the continuation of a state saved on 2 images differs from the serial one"

# Failures: the exit code of the serial run and one message
expect_failure() {   # expect_failure LABEL CASE
    local label=$1 case=$2 serial_rc rc messages
    "$serial_exe" "$case" --output "$tmp/fail-serial" --overwrite -q 2> "$tmp/serial.err"
    serial_rc=$?
    par "$case" --output "$tmp/fail-images" --overwrite -q 2> "$tmp/images.err"
    rc=$?
    messages=$(grep -c "^mpm_geo: error:" "$tmp/images.err")
    echo "--- $label: serial exit $serial_rc, 2 images exit $rc, $messages message(s)"
    [ "$serial_rc" -ne 0 ] || fail "$label: the serial run did not fail"
    [ "$rc" -eq "$serial_rc" ] || fail "$label: exit code $rc on 2 images, $serial_rc serially"
    [ "$messages" -eq 1 ] || { fail "$label: $messages messages on 2 images"; cat "$tmp/images.err"; }
}
printf '{"name": "broken", "domain": {"nx": 10,\n' > "$tmp/broken.json"
expect_failure "broken case file" "$tmp/broken.json"
"$python" - "$tmp/lost.json" <<'EOF'
import json, sys
c = json.load(open("tests/parallel/cases/par_block_moves_2d.json"))
c["name"] = "lost"
c["bodies"][0]["min"] = [0.8, 0.0]
c["bodies"][0]["max"] = [0.9, 0.1]
c["bodies"][0]["velocity"] = [-4.0, 0.0]
c["time"]["tend"] = 1.0
json.dump(c, open(sys.argv[1], "w"))
EOF
expect_failure "particle lost on one image" "$tmp/lost.json"
"$python" - "$tmp/far.json" <<'EOF'
import json, sys
c = json.load(open("tests/parallel/cases/par_terrain_slide_2d.json"))
c["name"] = "far"
c["contact"]["offset"] = [0.0, 5.0, 0.0]
json.dump(c, open(sys.argv[1], "w"))
EOF
expect_failure "STL terrain far from every slab" "$tmp/far.json"
grep -q "does not come within reach of the domain" "$tmp/images.err" \
    || fail "STL terrain far from every slab: the message does not say why"

if [ "$failed" -gt 0 ]; then
    echo "$failed check(s) failed"
    exit 1
fi
echo "all checks passed"

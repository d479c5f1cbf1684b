#!/usr/bin/env bash
# The outputs open in ParaView with both of its XDMF readers (real pvbatch): a 2D run and a 3D
# run with grid output (two materials each), a run on an STL terrain and its terrain.xdmf.
# check_xdmf_paraview.py checks, in one pvbatch call for all four files, Xdmf3ReaderS (what
# File > Open picks) and XDMFReader at the first and the last time: points and one vertex cell
# per particle, every declared array, nothing on stderr, Threshold on material against the
# counts in the HDF5 files (h5py). The run on 2 images is checked by tests/parallel.
# Exit code 77 (SKIP in CTest) when pvbatch is not installed (PVBATCH=path chooses another),
# a failure under make test (MPM_STRICT_TESTS=1).
# Usage: tests/cli/test_paraview.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
label=paraview
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh
pvbatch=${PVBATCH:-pvbatch}
need_tool "$pvbatch" "opening the XDMF files in ParaView"
need_python numpy h5py

expect 0 "2D run, two materials" -- "$exe" tests/cli/cases/paraview_2d.json \
    --output "$tmp/2d" --quiet
expect 0 "3D run with grid, two materials" -- "$exe" tests/cli/cases/paraview_3d.json \
    --output "$tmp/3d" --quiet
expect 0 "run on an STL terrain" -- "$exe" tests/cli/cases/terrain_block.json \
    --output "$tmp/terrain" --quiet

"$python" tests/cli/check_xdmf_paraview.py --pvbatch "$pvbatch" "$tmp/2d/paraview_2d.xdmf" \
    "$tmp/3d/paraview_3d.xdmf" "$tmp/terrain/terrain_block.xdmf" "$tmp/terrain/terrain.xdmf" \
    > "$tmp/pv.log" 2>&1
rc=$?
grep -c "^ok" "$tmp/pv.log" | sed 's/^/pvbatch checks passed: /'
if [ "$rc" -eq 0 ] && ! grep -q "^FAIL" "$tmp/pv.log"; then
    ok
else
    bad "ParaView readers (exit code $rc):"
    grep -v "^ok" "$tmp/pv.log"
fi
# both readers, the 2 checked times and a Threshold per material were really exercised
for what in "Xdmf3ReaderS paraview_2d.xdmf t = 0: 80 cells" \
    "XDMFReader paraview_3d.xdmf t = 0.02:" "Threshold material = 2 keeps 32" \
    "XDMFReader terrain.xdmf: 2000 triangles" \
    "Xdmf3ReaderT paraview_3d.xdmf: blocks ['grid', 'particles']"; do
    grep -qF "$what" "$tmp/pv.log" && ok || bad "the check did not report '$what'"
done

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

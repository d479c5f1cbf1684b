#!/usr/bin/env bash
# Bui et al. (2008) column collapse at 10 mm cells (800 particles, 1 s of flow): runs
# validation/bui2008/check.py --coarse with the given executable into a temporary folder and
# fails when the coarse band is missed (toe within 15 % of the experiment, a regression band;
# free surface RMS and height at the wall within 20 mm; see docs/validation.md). A few seconds
# on one thread.
# Usage: tests/cli/test_bui_coarse.sh path/to/mpm_geo   (run from the repository root)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 path/to/mpm_geo" >&2
    exit 2
fi
exe=$(realpath "$1")
python=.venv/bin/python
if [ ! -x "$python" ]; then
    echo "skip: $python not found (make deps creates it);" \
        "the Bui coarse check needs numpy, h5py and matplotlib"
    exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$python" validation/bui2008/check.py --coarse --quiet --exe "$exe" \
    --output "$tmp/run" --results "$tmp/results"
rc=$?
if [ "$rc" -ne 0 ]; then
    echo "FAIL [bui_coarse] check.py --coarse exited with code $rc" \
        "(1: a target missed, 2: the run failed)"
fi
exit "$rc"

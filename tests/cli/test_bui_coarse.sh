#!/usr/bin/env bash
# Bui et al. (2008) column collapse, the case file's 5 mm cells (3200 particles, 1 s of
# flow): runs validation/bui2008/check.py --coarse with the given executable into a temporary
# folder and fails when its regression band is missed (toe within 15 % of the experiment;
# free surface RMS and height at the wall within 10 mm; see docs/validation.md). About 30 s on
# one thread.
# Usage: tests/cli/test_bui_coarse.sh path/to/mpm_geo   (run from the repository root)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 path/to/mpm_geo" >&2
    exit 2
fi
exe=$(realpath "$1")
label=bui_coarse
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh
need_python numpy h5py matplotlib
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

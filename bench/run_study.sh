#!/usr/bin/env bash
# make study: accuracy against cost. Runs the three problems on one thread, then writes
# docs/accuracy-vs-cost.md and its figures (docs/study/*.png) from the CSV files in docs/study/:
#   mms     the manufactured solution (build/study_mms, a Fortran program)       ~ 4 min
#   column  the self-weight column through mpm_geo (bench/study_cases.py column) ~ 3 min
#   bui     the Bui et al. (2008) collapse through mpm_geo (bench/study_cases.py bui): the 2.5 mm
#           runs take minutes each on one thread, about 40 min in all (STUDY_BUI_DX shortens it)
#   cantilever  the Sadeghirad cantilever of issue 19 (bench/study_cantilever.py): the runs of
#           STUDY_CANTILEVER_RUNS appended to docs/study/cantilever.csv (the table of
#           docs/study/cantilever.md is written from them by hand); not a default part
# Usage: bench/run_study.sh [build-dir]
# Environment:
#   STUDY_PARTS         the parts to run (default "mms column bui"); a part not run keeps the CSV
#                       of its last run, which the page is written from
#   STUDY_COLUMN_CELLS  cells over the column's height (default "4 8 16 32 64 128")
#   STUDY_BUI_DX        cell sizes of the Bui runs [m] (default "0.01 0.005 0.0025"; a shorter
#                       ladder: "0.01 0.005", about 5 min)
#   STUDY_CANTILEVER_RUNS  "cells:shape:scheme:transfer:ppc ..." (default: CPDI and the cubic
#                       B-spline, MUSL FLIP, 2 x 2, at 0.25 and 0.125 m cells)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=docs/study
python=.venv/bin/python
parts=${STUDY_PARTS:-mms column bui}
column_cells=${STUDY_COLUMN_CELLS:-4 8 16 32 64 128}
bui_dx=${STUDY_BUI_DX:-0.01 0.005 0.0025}
cantilever_runs=${STUDY_CANTILEVER_RUNS:-0.25:cpdi:MUSL:flip:2 0.125:cpdi:MUSL:flip:2 \
0.25:bspline3:MUSL:flip:2 0.125:bspline3:MUSL:flip:2}
export OMP_NUM_THREADS=1
mkdir -p "$out"
[ -x "$python" ] || { echo "study: $python not found; run 'make deps'" >&2; exit 1; }
times="$out/study_times.txt"
touch "$times"

# Keep the time of each part in $times ("part seconds"), replacing that part's previous line.
record_time() {
    grep -v "^$1 " "$times" > "$times.tmp" || true
    echo "$1 $2" >> "$times.tmp"
    mv "$times.tmp" "$times"
}

need() {
    [ -x "$build/$1" ] || { echo "study: $build/$1 not found; run 'make build'" >&2; exit 1; }
}

for part in $parts; do
    start=$(date +%s)
    case "$part" in
        mms)
            need study_mms
            echo "study: manufactured solution (2 amplitudes x 2 shape functions x 3 schemes" \
                "x 6 resolutions)"
            "$build/study_mms" > "$out/mms.csv"
            ;;
        column)
            need mpm_geo
            echo "study: self-weight column (2 shape functions x 3 schemes x cells $column_cells)"
            # shellcheck disable=SC2086  # the ladder is a list of words
            "$python" bench/study_cases.py column --exe "$build/mpm_geo" --out "$out/column.csv" \
                --cells $column_cells
            ;;
        bui)
            need mpm_geo
            echo "study: Bui et al. (2008) collapse (2 shape functions x 3 schemes x dx $bui_dx m)"
            # shellcheck disable=SC2086
            "$python" bench/study_cases.py bui --exe "$build/mpm_geo" --out "$out/bui.csv" \
                --dx $bui_dx
            ;;
        cantilever)
            need mpm_geo
            echo "study: Sadeghirad cantilever (runs $cantilever_runs)"
            # shellcheck disable=SC2086
            "$python" bench/study_cantilever.py --exe "$build/mpm_geo" \
                --out "$out/cantilever.csv" --runs $cantilever_runs
            ;;
        *)
            echo "study: unknown part '$part' in STUDY_PARTS (parts: mms column bui" \
                "cantilever)" >&2
            exit 1
            ;;
    esac
    record_time "$part" $(( $(date +%s) - start ))
done

args=("$out/mms.csv" docs/accuracy-vs-cost.md --times "$times")
[ -f "$out/column.csv" ] && args+=(--column "$out/column.csv")
[ -f "$out/bui.csv" ] && args+=(--bui "$out/bui.csv")
"$python" bench/write_study.py "${args[@]}"

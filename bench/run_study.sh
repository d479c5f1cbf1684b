#!/usr/bin/env bash
# make study: accuracy against cost. Runs the study programs (bench/study_*.f90, built with
# the project) on one thread, then writes docs/accuracy-vs-cost.md and its figures.
# Usage: bench/run_study.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=docs/study
mkdir -p "$out"
[ -x "$build/study_mms" ] || { echo "study: $build/study_mms not found; run 'make build'" >&2; exit 1; }
echo "study: manufactured solution (2 amplitudes x 2 shape functions x 3 schemes x 6 resolutions)"
OMP_NUM_THREADS=1 "$build/study_mms" > "$out/mms.csv"
.venv/bin/python bench/write_study.py "$out/mms.csv" docs/accuracy-vs-cost.md

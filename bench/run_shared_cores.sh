#!/usr/bin/env bash
# Threads on shared cores (not a test): the default case run beside a busy process (a shell
# loop that keeps one core busy), and on idle cores, with 1 thread and with all threads,
# interleaved, printed as ratios of wall time to the 1-thread run of the same pair.
#  - "adaptive": the default, mpm_threads chooses the count of each step;
#  - "fixed": OMP_DYNAMIC=false, every step on all threads (what the runs did before; with
#    a busy process beside, capped at CAP seconds and printed as ">").
# The VM's own noise is 10-30 % from run to run; the pairs are run back to back so that a
# ratio compares runs made under the same conditions.
# Usage: bench/run_shared_cores.sh [path/to/mpm_geo] [case.json] [pairs]
set -uo pipefail
cd "$(dirname "$0")/.."
exe=${1:-build/mpm_geo}
case_file=${2:-inputs/base_case.json}
pairs=${3:-2}
cap=${CAP:-60}
threads=$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)
[ -x "$exe" ] || { echo "shared cores: $exe not found; run 'make build' first" >&2; exit 1; }
out=$(mktemp -d)
busy=""
cleanup() { [ -n "$busy" ] && kill "$busy" 2> /dev/null; rm -rf "$out"; }
trap cleanup EXIT

# run THREADS adaptive|fixed: wall seconds of one run, or ">cap" when it did not end within
# cap seconds (adaptive: OMP_DYNAMIC unset, not true, which would let libgomp cut the count by
# the load average)
run() {
    local t=$1 fixed=$2 start end rc
    local env=(env -u OMP_DYNAMIC OMP_NUM_THREADS="$t")
    [ "$fixed" = fixed ] && env+=(OMP_DYNAMIC=false)
    rm -f "$out/threads_$t$fixed"
    start=$(date +%s.%N)
    "${env[@]}" timeout "$cap" "$exe" "$case_file" --overwrite --output "$out/run" \
        > "$out/log" 2>&1
    rc=$?
    end=$(date +%s.%N)
    if [ "$rc" -eq 124 ]; then echo ">$cap"; return; fi
    [ "$rc" -eq 0 ] || { echo "shared cores: the run failed:" >&2; cat "$out/log" >&2; exit 1; }
    awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }'
    # the summary's thread line ("2 at most (adaptive; steps on 1: 99.8 %, 2: 0.2 %)")
    sed -n 's/^  threads *//p' "$out/log" | tr -s ' ' > "$out/threads_$t$fixed"
}
ratio() { case $1 in ">"*) echo ">$(awk -v a="${1#>}" -v b="$2" 'BEGIN { printf "%.2f", a / b }')" ;;
    *) awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }' ;; esac; }

echo "shared cores: $case_file, $threads threads at most, $pairs interleaved sets per condition"
printf '%-8s %4s %10s %12s %9s %12s %9s\n' cores set "1 thread" adaptive ratio fixed ratio
for condition in idle busy; do
    if [ "$condition" = busy ]; then
        bash -c 'while :; do :; done' &
        busy=$!
    fi
    for k in $(seq 1 "$pairs"); do
        one=$(run 1 adaptive)
        adaptive=$(run "$threads" adaptive)
        fixed=$(run "$threads" fixed)
        printf '%-8s %4s %10s %12s %9s %12s %9s\n' "$condition" "$k" "$one" "$adaptive" \
            "$(ratio "$adaptive" "$one")" "$fixed" "$(ratio "$fixed" "$one")"
        echo "BENCH shared_cores cores=$condition set=$k one_s=$one adaptive_s=$adaptive" \
            "fixed_s=$fixed threads=$threads adaptive_threads=\"$(cat "$out/threads_${threads}adaptive" \
            2> /dev/null)\"" >> "$out/lines"
    done
    if [ -n "$busy" ]; then kill "$busy"; wait "$busy" 2> /dev/null; busy=""; fi
done
cat "$out/lines"

#!/usr/bin/env bash
# Speed benchmarks of mpm_geo (not a test): runs each case in bench/cases/ with 1 and 2
# OpenMP threads (fixed: OMP_DYNAMIC=false, so each run keeps its count) and prints particles, nodes, steps, wall time, particle-steps per second,
# memory (peak, bytes per particle and per node) and the time per phase of the step, as
# tables and as one machine-readable line per run ("BENCH key=value ..."), after the memory
# bandwidth of the machine (STREAM's triad, "TRIAD key=value ...").
# Usage: bench/run_bench.sh [path/to/mpm_geo] [case.json ...]
set -euo pipefail
cd "$(dirname "$0")/.."
exe=${1:-build/mpm_geo}
shift || true
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(bench/cases/*.json)
[ -x "$exe" ] || { echo "bench: $exe not found; run 'make build' first" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "mpm_geo: $($exe --version)"
# the memory bandwidth the cases are measured against (STREAM's triad, bench/stream_triad.f90,
# built beside mpm_geo); docs/performance.md states the fraction of it each case reaches
triad="$(dirname "$exe")/stream_triad"
if [ -x "$triad" ]; then
    for t in 1 2; do
        OMP_NUM_THREADS=$t OMP_DYNAMIC=false OMP_PROC_BIND=true "$triad" > "$out/triad-$t.log"
        cat "$out/triad-$t.log"
    done
else
    echo "bench: $triad not found (built by 'make build'); no bandwidth figure" >&2
fi
printf '%-16s %7s %10s %9s %7s %9s %14s %10s %12s %10s\n' case threads particles nodes steps \
    wall_s particle-steps/s peak_MB bytes/particle bytes/node
for c in "${cases[@]}"; do
    name=$(basename "$c" .json)
    for t in 1 2; do
        log="$out/$name-$t.log"
        OMP_NUM_THREADS=$t OMP_DYNAMIC=false OMP_PROC_BIND=true /usr/bin/env "$exe" "$c" --output "$out/$name-$t" \
            > "$log" 2>&1 || { echo "bench: $name failed:"; cat "$log"; exit 1; }
        get() { awk -v k="$1" '$1 == k {print $2}' "$log"; }
        parts=$(get particles); nodes=$(get nodes); steps=$(get steps)
        wall=$(awk '$1 == "wall" {print $3}' "$log")
        pps=$(awk '$1 == "particle-steps/s" {print $2}' "$log")
        peak=$(awk '$1 == "peak" {print $3}' "$log")
        bpp=$(awk '$1 == "particle" && $2 == "storage" {print $3}' "$log")
        bpn=$(awk '$1 == "grid" && $2 == "storage" {print $3}' "$log")
        # "time per phase  sorting=1.0 P2G=2.0 ... s" -> "sorting_s=1.0 P2G_s=2.0 ..."
        phases=$(awk '$1 == "time" && $2 == "per" && $3 == "phase" {
            for (i = 4; i < NF; i++) { split($i, kv, "="); printf "%s%s_s=%s", (i > 4 ? " " : ""), kv[1], kv[2] } }' "$log")
        printf '%-16s %7s %10s %9s %7s %9.2f %14.4g %10.1f %12s %10s\n' "$name" "$t" "$parts" \
            "$nodes" "$steps" "$wall" "$pps" "$peak" "$bpp" "$bpn"
        echo "$name threads=$t $phases" >> "$out/phases"
        echo "BENCH case=$name threads=$t particles=$parts nodes=$nodes steps=$steps" \
             "wall_s=$wall particle_steps_per_s=$pps peak_mb=$peak bytes_per_particle=$bpp" \
             "bytes_per_node=$bpn $phases" >> "$out/lines"
    done
done
echo
echo "time per phase [s] (sorting: shape functions, particle order, chunks; P2G: scatters;"
echo "nodal: nodal update; G2P: velocities, positions, MUSL remap; stress: stress update;"
echo "other: time step, guard, energies; output: files)"
cat "$out/phases"
echo
cat "$out/lines"
grep -h '^TRIAD' "$out"/triad-*.log 2>/dev/null || true
echo
# Cost against size (issue 20: particle-steps per second should not fall as the particle arrays
# leave the caches): the B2 block at 2 x 2 particles per cell with n cells per metre, so
# 4 n^2 particles (n = 64, 125, 250, 500: 16 384, 62 500, 250 000 and 1 000 000), the time step
# scaled with the cell (the CFL number of B2), 200 steps, one thread, no output.
sizes=${BENCH_SIZES:-64 125 250 500}
echo
echo "B2 against size (1 thread, 200 steps)"
printf '%-10s %10s %9s %14s %9s\n' cells/m particles wall_s particle-steps/s relative
first_pps=""
for n in $sizes; do
    python3 - "$n" "$out/b2_n$n.json" <<'PY'
import json, sys
n = int(sys.argv[1])
case = json.load(open("bench/cases/b2_elastic_2d.json"))
dx = 1.0 / n
case["name"] = f"b2_elastic_2d_n{n}"
case["domain"].update(nx=2 * n, ny=2 * n, dx=dx)
dt = 2.4e-5 * dx / 0.004          # B2's step at its 0.004 m cells, scaled with the cell
case["time"] = {"tend": 200 * dt, "dt": dt}
json.dump(case, open(sys.argv[2], "w"))
PY
    log="$out/b2_n$n.log"
    OMP_NUM_THREADS=1 OMP_DYNAMIC=false OMP_PROC_BIND=true "$exe" "$out/b2_n$n.json" \
        --output "$out/b2_n$n" > "$log" 2>&1 || { echo "bench: B2 at n = $n failed:"; cat "$log"; exit 1; }
    parts=$(awk '$1 == "particles" {print $2}' "$log")
    wall=$(awk '$1 == "wall" {print $3}' "$log")
    pps=$(awk '$1 == "particle-steps/s" {print $2}' "$log")
    [ -n "$first_pps" ] || first_pps=$pps
    printf '%-10s %10s %9.2f %14.4g %9.2f\n' "$n" "$parts" "$wall" "$pps" \
        "$(awk -v a="$pps" -v b="$first_pps" 'BEGIN { print a / b }')"
    echo "BENCH case=b2_elastic_2d_n$n threads=1 particles=$parts wall_s=$wall" \
         "particle_steps_per_s=$pps" >> "$out/size_lines"
    rm -rf "$out/b2_n$n"
done
cat "$out/size_lines"
echo
# A sparse grid's cost (issue 20): b3_small_slide_2d (1 600 particles in 800 000 nodes) against
# the same block in a tight domain (40 x 30 cells, the block as far from the walls and as high
# above the base), one thread, three interleaved pairs: the ratio of the median wall times
# (target: within 10 %) and of the peak memory.
python3 - "$out/b3_small_slide_2d_tight.json" <<'PY'
import json, sys
case = json.load(open("bench/cases/b3_small_slide_2d.json"))
case["name"] = "b3_small_slide_2d_tight"
case["domain"].update(nx=40, ny=30)
body = case["bodies"][0]
width = body["max"][0] - body["min"][0]
body["min"][0] = 0.04
body["max"][0] = 0.04 + width
json.dump(case, open(sys.argv[1], "w"))
PY
echo "b3_small_slide_2d against the same block in a tight domain (1 thread, 3 interleaved pairs)"
for round in 1 2 3; do
    for c in bench/cases/b3_small_slide_2d.json "$out/b3_small_slide_2d_tight.json"; do
        name=$(basename "$c" .json)
        log="$out/$name-$round.log"
        OMP_NUM_THREADS=1 OMP_DYNAMIC=false OMP_PROC_BIND=true "$exe" "$c" --output "$out/$name" \
            > "$log" 2>&1 || { echo "bench: $name failed:"; cat "$log"; exit 1; }
        echo "$name $(awk '$1 == "wall" {print $3}' "$log") $(awk '$1 == "peak" {print $3}' "$log")" \
            >> "$out/sparse"
        rm -rf "${out:?}/$name"
    done
done
awk '{ wall[$1] = wall[$1] " " $2; peak[$1] = $3 }
     function median(list,   v, n, i, j, t) {
         n = split(list, v, " ")
         for (i = 2; i <= n; i++) for (j = i; j > 1 && v[j - 1] + 0 > v[j] + 0; j--) {
             t = v[j]; v[j] = v[j - 1]; v[j - 1] = t }
         return v[int((n + 1) / 2)] }
     END {
         big = "b3_small_slide_2d"; tight = "b3_small_slide_2d_tight"
         printf "%-26s %10s %10s\n", "case", "wall_s", "peak_MB"
         printf "%-26s %10.3f %10.1f\n", big, median(wall[big]), peak[big]
         printf "%-26s %10.3f %10.1f\n", tight, median(wall[tight]), peak[tight]
         printf "BENCH sparse_grid wall_ratio=%.3f peak_ratio=%.2f\n", \
             median(wall[big]) / median(wall[tight]), peak[big] / peak[tight]
     }' "$out/sparse"
echo
# the default case beside a busy process, with the thread count chosen per step (mpm_threads)
bash bench/run_shared_cores.sh "$exe"

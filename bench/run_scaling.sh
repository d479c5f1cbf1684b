#!/usr/bin/env bash
# Strong scaling of the coarray build (not a test): runs each case with the serial build on
# 1 and 2 threads and with the coarray build on 1 and 2 images (1 thread each), and prints
# wall time, particle-steps per second and the speed-up over one serial thread, as a table
# and as machine-readable lines ("SCALING key=value ...").
# Usage: bench/run_scaling.sh [case.json ...]   (default: bench/cases/b1_collapse_3d.json and
#        b2_elastic_2d.json; needs build/mpm_geo and build-caf/mpm_geo: make build coarray)
set -euo pipefail
cd "$(dirname "$0")/.."
serial=build/mpm_geo
caf=build-caf/mpm_geo
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(bench/cases/b1_collapse_3d.json bench/cases/b2_elastic_2d.json)
for exe in "$serial" "$caf"; do
    [ -x "$exe" ] || { echo "run_scaling: $exe not found (make build coarray)" >&2; exit 1; }
done
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_osc=rdma,pt2pt
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
printf '%-18s %-22s %9s %16s %9s\n' case run wall_s particle-steps/s speed-up
for c in "${cases[@]}"; do
    name=$(basename "$c" .json)
    base=""
    for run in "serial 1 thread" "serial 2 threads" "1 image" "2 images"; do
        log="$out/$name.log"
        case "$run" in
            "serial 1 thread") OMP_NUM_THREADS=1 OMP_PROC_BIND=true "$serial" "$c" \
                --output "$out/o" --overwrite > "$log" 2>&1 ;;
            "serial 2 threads") OMP_NUM_THREADS=2 OMP_PROC_BIND=true "$serial" "$c" \
                --output "$out/o" --overwrite > "$log" 2>&1 ;;
            "1 image") OMP_NUM_THREADS=1 cafrun -np 1 "$caf" "$c" --output "$out/o" \
                --overwrite > "$log" 2>&1 ;;
            "2 images") OMP_NUM_THREADS=1 cafrun -np 2 "$caf" "$c" --output "$out/o" \
                --overwrite > "$log" 2>&1 ;;
        esac
        wall=$(awk '$1 == "wall" {print $3}' "$log")
        pps=$(awk '$1 == "particle-steps/s" {print $2}' "$log")
        [ -n "$base" ] || base=$wall
        speedup=$(awk -v a="$base" -v b="$wall" 'BEGIN {printf "%.2f", a / b}')
        printf '%-18s %-22s %9.2f %16.4g %9s\n' "$name" "$run" "$wall" "$pps" "$speedup"
        echo "SCALING case=$name run=${run// /_} wall_s=$wall particle_steps_per_s=$pps" \
             "speedup=$speedup" >> "$out/lines"
    done
done
echo
cat "$out/lines"

#!/usr/bin/env bash
# Side by side with a peer code: builds MPM-Geomechanics (C++, fabricix/MPM-Geomechanics) from a
# source folder the user gives and runs it and mpm_geo on scene B1 of ../shared/BENCHMARKS.md
# (3D Mohr-Coulomb column collapse, 16 000 particles, cpGIMP / GIMP, MUSL, dt 1.83e-4 s, 0.5 s)
# with 1 and 2 threads, interleaved (mpm_geo, peer, mpm_geo, peer, ...), and prints the wall
# times and the ratio of the medians. Speed is a ratio measured in one run on one machine:
# never compare with figures of another day.
# Usage: bench/run_peers.sh [PEER_SOURCE] [build-dir]   (or PEER_SOURCE=... make bench-peers)
#   PEER_SOURCE   a clone of MPM-Geomechanics (its build/CMake/CMakeLists.txt); without it the
#                 script says so and exits 0 (nothing to compare)
#   PEER_ROUNDS   interleaved rounds per thread count (default 1: B1 takes the peer about
#                 140 s on one thread)
#   PEER_THREADS  thread counts (default "1 2")
# The peer is built from a copy of the source in <build-dir>/peers/ (its CMakeLists writes the
# executable next to itself, so the user's folder is not touched), Release, its own flags.
# Its input is bench/peers/b1_mpm_geomechanics.json with n_threads set per run; it runs in a
# scratch folder (it writes its results into the working directory).
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir=${1:-${PEER_SOURCE:-}}
build=${2:-build}
rounds=${PEER_ROUNDS:-1}
threads_list=${PEER_THREADS:-1 2}
exe=$build/mpm_geo
case_file=bench/cases/b1_collapse_3d.json
peer_input=bench/peers/b1_mpm_geomechanics.json

if [ -z "$source_dir" ]; then
    echo "run_peers: no peer source given: skipped (give a clone of fabricix/MPM-Geomechanics:"
    echo "  bench/run_peers.sh /path/to/MPM-Geomechanics, or PEER_SOURCE=/path make bench-peers)"
    exit 0
fi
if [ ! -f "$source_dir/build/CMake/CMakeLists.txt" ]; then
    echo "run_peers: $source_dir/build/CMake/CMakeLists.txt not found: PEER_SOURCE must be a" \
        "clone of MPM-Geomechanics" >&2
    exit 2
fi
[ -x "$exe" ] || { echo "run_peers: $exe not found; run 'make build' first" >&2; exit 2; }

peer_root=$build/peers/MPM-Geomechanics
peer_exe=$peer_root/build/CMake/MPM-Geomechanics
if [ ! -x "$peer_exe" ]; then
    echo "run_peers: building MPM-Geomechanics from a copy of $source_dir"
    rm -rf "$peer_root"
    mkdir -p "$build/peers"
    # the sources only (no .git, no earlier builds)
    (cd "$source_dir" && tar --exclude=.git --exclude=build/CMake/build -cf - .) |
        (mkdir -p "$peer_root" && cd "$peer_root" && tar -xf -)
    cmake -S "$peer_root/build/CMake" -B "$peer_root/build/CMake/build" \
        -DCMAKE_BUILD_TYPE=Release > "$build/peers/cmake.log" 2>&1 ||
        { echo "run_peers: cmake of the peer failed (see $build/peers/cmake.log)" >&2; exit 2; }
    cmake --build "$peer_root/build/CMake/build" -j 2 > "$build/peers/build.log" 2>&1 ||
        { echo "run_peers: build of the peer failed (see $build/peers/build.log)" >&2; exit 2; }
fi
[ -x "$peer_exe" ] || { echo "run_peers: the peer's build made no $peer_exe" >&2; exit 2; }
peer_exe=$(cd "$(dirname "$peer_exe")" && pwd)/$(basename "$peer_exe")

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
python=.venv/bin/python
[ -x "$python" ] || python=python3

# wall time of a command [s]
seconds() {
    local t0 t1
    t0=$(date +%s.%N)
    "$@" > "$scratch/last.log" 2>&1 || { echo "run_peers: failed: $*" >&2; tail -5 "$scratch/last.log" >&2; exit 2; }
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc
}

echo "B1 collapse, $(nproc) cores, $(date -u +%Y-%m-%d), $("$exe" --version | head -1)," \
    "MPM-Geomechanics from $source_dir ($(git -C "$source_dir" rev-parse --short HEAD 2>/dev/null || echo 'no git'))"
printf "%-8s %-6s %14s %18s\n" threads round "mpm_geo [s]" "MPM-Geomechanics [s]"
summary=()
for threads in $threads_list; do
    ours=()
    theirs=()
    "$python" - "$peer_input" "$scratch/peer_$threads.json" "$threads" <<'PY'
import json, sys
case = json.load(open(sys.argv[1]))
case["n_threads"] = int(sys.argv[3])
json.dump(case, open(sys.argv[2], "w"), indent=1)
PY
    for round in $(seq "$rounds"); do
        a=$(OMP_NUM_THREADS=$threads seconds "$exe" "$case_file" --output "$scratch/mpm_geo" \
            --overwrite -q)
        mkdir -p "$scratch/peer_run"
        b=$(cd "$scratch/peer_run" && OMP_NUM_THREADS=$threads seconds "$peer_exe" \
            "$scratch/peer_$threads.json")
        rm -rf "$scratch/peer_run"
        # the same scene: the peer prints its particle count ("Particles : 16000")
        count=$(grep -o "Particles : [0-9]*" "$scratch/last.log" | head -1 | grep -o "[0-9]*$" || true)
        if [ "$count" != 16000 ]; then
            echo "run_peers: the peer ran ${count:-an unknown number of} particles, not the 16 000 of B1" >&2
            exit 2
        fi
        ours+=("$a")
        theirs+=("$b")
        printf "%-8s %-6s %14.1f %18.1f\n" "$threads" "$round" "$a" "$b"
    done
    summary+=("$("$python" -c "
import statistics, sys
a = statistics.median([float(x) for x in sys.argv[2].split()])
b = statistics.median([float(x) for x in sys.argv[3].split()])
print(f'{sys.argv[1]} thread(s): mpm_geo {a:.1f} s, MPM-Geomechanics {b:.1f} s: {b / a:.2f} x')
" "$threads" "${ours[*]}" "${theirs[*]}")")
done
printf '%s\n' "${summary[@]}"

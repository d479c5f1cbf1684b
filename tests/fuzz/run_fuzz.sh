#!/usr/bin/env bash
# Fuzz the case reader with AFL++ for a fixed time (make fuzz; docs/testing.md).
#
#   tests/fuzz/run_fuzz.sh [seconds]     (run from anywhere; default FUZZ_SECONDS or 600)
#
# Builds build-fuzz/ (Debug flags: bounds checks, FPE traps; AFL++ edge coverage from the GCC
# plugin tests/fuzz/afl_gcc_cov.cc), seeds AFL++ with the small case files of inputs/,
# validation/ and tests/bad_inputs/, fuzzes tests/fuzz/fuzz_case_reader with the dictionary
# tests/fuzz/json.dict, then lists the crashes and hangs found under build-fuzz/afl-out/.
# Exit status: 0 nothing found, 1 a crash or a hang was found, 2 the fuzzer could not run.
# The findings of the previous run are kept in build-fuzz/afl-out.prev/.
set -euo pipefail

seconds=${1:-${FUZZ_SECONDS:-600}}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${FUZZ_BUILD_DIR:-$root/build-fuzz}
max_seed_bytes=4096     # AFL++ works best with small seeds; the big validation cases add nothing
timeout_ms=2000         # a case file is read in milliseconds: 2 s is a hang
memory_mb=2048          # an allocation beyond this fails, and a failed allocation is a crash
cd "$root"

case "$seconds" in
    '' | *[!0-9]*) echo "run_fuzz.sh: the time must be a whole number of seconds, not '$seconds'" >&2
        exit 2 ;;
esac
for tool in afl-fuzz afl-tmin; do
    if ! command -v "$tool" > /dev/null 2>&1; then
        echo "run_fuzz.sh: $tool not found: run scripts/install_deps.sh --with-fuzz" >&2
        exit 2
    fi
done

# Build: Debug flags so runtime checks and floating-point traps end the run; no OpenMP and no
# test programs (only the harness is fuzzed).
if [ ! -f "$build/CMakeCache.txt" ]; then
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DMPM_FUZZ=ON -DMPM_OPENMP=OFF \
        -DMPM_TESTS=OFF || { rm -f "$build/CMakeCache.txt"; exit 2; }
fi
cmake --build "$build" -j "$(nproc 2> /dev/null || echo 2)" --target fuzz_case_reader || exit 2
harness=$build/fuzz_case_reader

# Seeds: the small case files, each content once (named by its hash).
seeds=$build/afl-in
rm -rf "$seeds"
mkdir -p "$seeds"
find inputs validation tests/bad_inputs -maxdepth 2 -name '*.json' -not -path '*/results/*' \
    -size -"$((max_seed_bytes + 1))"c -print0 |
    while IFS= read -r -d '' f; do
        cp "$f" "$seeds/$(sha1sum "$f" | cut -c1-16).json"
    done
echo "run_fuzz.sh: $(find "$seeds" -type f | wc -l) seed cases, fuzzing for $seconds s"

out=$build/afl-out
if [ -d "$out" ]; then
    rm -rf "$out.prev"
    mv "$out" "$out.prev"
fi

# Non-interactive, root-friendly settings; the machine is shared, so no CPU pinning.
export AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1 \
    AFL_NO_AFFINITY=1
status=0
afl-fuzz -i "$seeds" -o "$out" -x tests/fuzz/json.dict -t "$timeout_ms" -m "$memory_mb" \
    -V "$seconds" -- "$harness" @@ > "$build/afl-fuzz.log" 2>&1 || status=$?
stats=$out/default/fuzzer_stats
if [ ! -f "$stats" ]; then
    echo "run_fuzz.sh: afl-fuzz did not run (status $status); its output:" >&2
    tail -n 30 "$build/afl-fuzz.log" >&2
    exit 2
fi

stat_value() {
    awk -F' *: *' -v key="$1" '$1 == key { print $2 }' "$stats"
}
echo "run_fuzz.sh: $(stat_value execs_done) runs ($(stat_value execs_per_sec)/s)," \
    "$(stat_value corpus_count) cases in the corpus, $(stat_value edges_found) edges" \
    "($(stat_value bitmap_cvg) of the map)"
found=0
for kind in crashes hangs; do
    files=$(find "$out/default/$kind" -name 'id:*' -type f 2> /dev/null | sort)
    count=$(printf '%s' "$files" | grep -c . || true)
    echo "run_fuzz.sh: $count $kind"
    if [ "$count" -gt 0 ]; then
        found=1
        printf '%s\n' "$files" | sed 's/^/    /'
    fi
done
if [ "$found" = 1 ]; then
    echo "run_fuzz.sh: reproduce with '$harness <file>'; minimise with" \
         "'afl-tmin -i <file> -o min.json -- $harness @@'; fix the reader, then add the case" \
         "to tests/bad_inputs/ (docs/testing.md)"
    exit 1
fi

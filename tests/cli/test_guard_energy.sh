#!/usr/bin/env bash
# The blow-up guard sees energy being created (issue 19): inputs/elastic_cantilever.json, the
# shipped example, run to t = 2 s turns unstable after about 0.5 s (the residual of its energy
# balance, within +-0.5 J of its 55 J of gravity work before, grows to 7 000 J by 2 s, with the
# volumes of some particles 8 times their start). The guard must stop it with exit code 3 and
# a message naming the step, the particle and the quantity, never let it end with exit 0; the
# guard of an older build (kinetic energy above 10 times the largest energy so far) never
# stopped it. The same beam up to 0.45 s, healthy, must not be stopped. About 10 s on one
# thread.
# Usage: tests/cli/test_guard_energy.sh path/to/mpm_geo   (run from the repository root)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 path/to/mpm_geo" >&2
    exit 2
fi
exe=$(realpath "$1")
label=guard_energy
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh

# the shipped case with another end time and few outputs
beam() {
    sed -e "s/\"tend\": 1.0/\"tend\": $1/" -e 's/"interval": 0.02/"interval": 1.0/' \
        inputs/elastic_cantilever.json > "$tmp/beam_$1.json"
    grep -q "\"tend\": $1" "$tmp/beam_$1.json" || bad "could not set tend = $1 in the case"
}

beam 0.45
expect 0 "healthy beam (t <= 0.45 s) runs to its end" -- \
    "$exe" -q --output "$tmp/healthy" "$tmp/beam_0.45.json"

beam 2.0
expect 3 "unstable beam (t = 2 s) is stopped with exit code 3" -- \
    "$exe" -q --output "$tmp/unstable" "$tmp/beam_2.0.json"
contains "the run became unstable: it created energy" "the message names the quantity"
contains "energy residual" "the message gives the energy created"
contains "fastest particle " "the message names the particle"
contains "step " "the message names the step"
# stopped soon after it turned unstable (t ~ 0.5 s), far from the end time
step_time=$(sed -n 's/.*step [0-9]*, t = *\([0-9.E+-]*\) s.*/\1/p' "$tmp/out" | head -1)
if [ -n "$step_time" ] && awk -v t="$step_time" 'BEGIN { exit !(t > 0.45 && t < 1.5) }'; then
    ok
else
    bad "stopped at t = '$step_time' s, expected between 0.45 s and 1.5 s"; cat "$tmp/out"
fi

echo "guard_energy: $passed checks passed, $failed failed"
[ "$failed" -eq 0 ]

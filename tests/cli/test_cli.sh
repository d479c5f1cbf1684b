#!/usr/bin/env bash
# Command-line behaviour of mpm_geo: options, exit codes, messages, output folder rules,
# save_state/load_state (ParaView opening the outputs: test_paraview.sh).
# Usage: tests/cli/test_cli.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
label=cli
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh

cat > "$tmp/small.json" <<'JSON'
{
  "name": "small",
  "domain": {"nx": 12, "ny": 8, "dx": 0.05, "boundaries": {"ymin": "fixed", "xmin": "sliding", "xmax": "sliding"}},
  "particles": {"ppc": 2},
  "materials": [{"name": "soil", "type": "linear_elastic", "E": 1e5, "nu": 0.3, "rho": 1500}],
  "bodies": [{"name": "block", "material": "soil", "min": [0.1, 0.0], "max": [0.4, 0.2]}],
  "gravity": [0, -9.81],
  "time": {"tend": 0.05, "cfl": 0.5},
  "output": {"interval": 0.01},
  "save_state": "STATE"
}
JSON
sed -i "s#STATE#$tmp/state/small.h5#" "$tmp/small.json"

expect 0 "--help" -- "$exe" --help
contains "usage: mpm_geo" "--help"
contains "exit codes" "--help"
expect 0 "--version" -- "$exe" --version
contains "mpm_geo " "--version"
expect 2 "no arguments" -- "$exe"
contains "no case file given" "no arguments"
expect 2 "unknown option" -- "$exe" --frobnicate x.json
contains "unknown option '--frobnicate'" "unknown option"
expect 2 "missing case file" -- "$exe" "$tmp/does_not_exist.json"
contains "does_not_exist.json" "missing case file"
expect 2 "--output without value" -- "$exe" "$tmp/small.json" --output
contains "needs a value" "--output without value"
# an option is not the value of the option before it: nothing runs into a folder "--check"
expect 2 "-o --check" -- env -C "$tmp" "$exe" "$tmp/small.json" -o --check
contains "option -o needs a value, got the option '--check'" "-o --check"
[ ! -e "$tmp/--check" ] && ok || bad "-o --check created a folder '--check'"
expect 2 "--input --quiet" -- env -C "$tmp" "$exe" --input --quiet "$tmp/small.json"
contains "option --input needs a value, got the option '--quiet'" "--input --quiet"
expect 2 "--output -x (a name starting with '-')" -- env -C "$tmp" "$exe" "$tmp/small.json" \
    --output -x
contains "got the option '-x'" "--output -x"
[ ! -e "$tmp/-x" ] && ok || bad "--output -x created a folder '-x'"
long_name=$(printf 'x%.0s' $(seq 256))
expect 2 "--output with a folder name of 256 bytes" -- "$exe" "$tmp/small.json" --output \
    "$tmp/$long_name"
contains "not a usable folder name: its part 'xxxxxxxxxxxxxxxxxxxx...' is 256 bytes long, at most 255" \
    "--output with a folder name of 256 bytes"
expect 2 "--checkpoint-steps --check" -- "$exe" "$tmp/small.json" --checkpoint-steps --check
contains "option --checkpoint-steps needs a value, got the option '--check'" \
    "--checkpoint-steps --check"
expect 2 "--checkpoint-minutes --quiet" -- "$exe" "$tmp/small.json" --checkpoint-minutes \
    --quiet
contains "needs a value, got the option '--quiet'" "--checkpoint-minutes --quiet"

# --check validates and prints the set-up, writes nothing
expect 0 "--check" -- "$exe" --check "$tmp/small.json" --output "$tmp/run"
contains "is valid" "--check"
[ ! -e "$tmp/run" ] && ok || bad "--check must not create the output folder"

# a real run with the manual's --input form
expect 0 "run" -- "$exe" --input "$tmp/small.json" --output "$tmp/run"
contains "particle-steps/s" "run summary"
for f in small.xdmf history.csv particles_000000.h5; do
    [ -s "$tmp/run/$f" ] && ok || bad "run did not write $f"
done
[ -s "$tmp/state/small.h5" ] && ok || bad "save_state did not write the state file"
head -1 "$tmp/run/history.csv" | grep -q "^time,step,kinetic_energy,elastic_energy,potential_energy,plastic_work,viscous_work,damping_work,friction_work,load_work,boundary_work,transfer_loss,total,residual" \
    && ok || bad "history.csv header"
nhist=$(wc -l < "$tmp/run/history.csv")
[ "$nhist" -ge 3 ] && ok || bad "history.csv has $nhist lines"

# an output interval far below the time step (below the rounding of the time): an output
# every step, and the run ends (the schedule once spun at 100 % CPU, deaf to SIGTERM)
sed -e 's#"interval": 0.01#"interval": 1e-20#' -e 's#"save_state": ".*"#"name": "tiny"#' \
    -e 's#"name": "small",##' "$tmp/small.json" > "$tmp/tiny.json"
expect 0 "--check, output.interval below the time step" -- "$exe" --check "$tmp/tiny.json"
contains "below the time step" "--check notes an output interval below the time step"
expect 0 "output.interval = 1e-20" -- timeout -k 5 30 "$exe" "$tmp/tiny.json" --output \
    "$tmp/tiny" --quiet
last_step=$(tail -1 "$tmp/tiny/history.csv" | cut -d, -f2)
nfiles=$(find "$tmp/tiny" -name 'particles_*.h5' | wc -l)
[ "$nfiles" -eq $((last_step + 1)) ] && [ "$last_step" -gt 5 ] && ok \
    || bad "output.interval = 1e-20: $nfiles particle files for $last_step steps"
# ... and answers SIGTERM within a step: exit 4 and a checkpoint in a few seconds (10 s: a
# loaded machine, a Debug build; the spinning schedule never answered)
sed 's#"interval": 0.03#"interval": 1e-20#' tests/cli/cases/restart_collapse.json \
    > "$tmp/tiny_long.json"
timeout -k 5 60 "$exe" "$tmp/tiny_long.json" --output "$tmp/tiny_long" --quiet \
    > "$tmp/out" 2>&1 &
pid=$!
for _ in $(seq 1 6000); do [ -f "$tmp/tiny_long/particles_000004.h5" ] && break; sleep 0.01; done
start=$SECONDS
# the signal goes to mpm_geo, not to timeout around it (timeout, signalled at its start, could
# die of it: exit 143 before mpm_geo saw anything, 2 runs in 6 of a loaded Debug build)
child=$(pgrep -P "$pid" 2>/dev/null | head -1)
kill -TERM "${child:-$pid}"
wait "$pid"
rc=$?
[ "$rc" -eq 4 ] && [ -s "$tmp/tiny_long/checkpoint.h5" ] && [ $((SECONDS - start)) -le 10 ] && ok \
    || { bad "SIGTERM, output.interval = 1e-20: exit code $rc after $((SECONDS - start)) s"; \
         cat "$tmp/out"; }

# an existing output folder is not overwritten silently
sum_before=$(md5sum "$tmp/run/history.csv")
expect 2 "existing output folder" -- "$exe" "$tmp/small.json" --output "$tmp/run" --quiet
contains "exists already" "existing output folder"
contains "--overwrite" "existing output folder"
[ "$(md5sum "$tmp/run/history.csv")" = "$sum_before" ] && ok || bad "refused run changed files"
expect 0 "--overwrite" -- "$exe" "$tmp/small.json" --output "$tmp/run" --overwrite --quiet
[ ! -s "$tmp/out" ] && ok || bad "--quiet printed output"
# overwriting with fewer outputs leaves no stale particle files of the longer run
sed -e 's#"interval": 0.01#"interval": 0.025#' "$tmp/small.json" > "$tmp/fewer.json"
expect 0 "--overwrite with fewer outputs" -- "$exe" "$tmp/fewer.json" --output "$tmp/run" --overwrite --quiet
[ -e "$tmp/run/particles_000002.h5" ] && [ ! -e "$tmp/run/particles_000003.h5" ] && ok \
    || bad "overwritten folder keeps stale particle files: $(ls "$tmp/run")"

# load_state: a new run starting from the saved state
sed -e 's#"bodies": \[.*\],#"load_state": "LOAD",#' -e "s#\"save_state\": \".*\"#\"name\": \"loaded\"#" \
    -e 's#"name": "small",##' "$tmp/small.json" > "$tmp/loaded.json"
sed -i "s#LOAD#$tmp/state/small.h5#" "$tmp/loaded.json"
expect 0 "load_state run" -- "$exe" "$tmp/loaded.json" --output "$tmp/loaded" --quiet
# a state from an incompatible case is refused
sed -e 's#"dx": 0.05#"dx": 0.04#' "$tmp/loaded.json" > "$tmp/incompatible.json"
expect 2 "incompatible state" -- "$exe" "$tmp/incompatible.json" --output "$tmp/inc"
contains "small.h5" "incompatible state names the state file"

# a particle that leaves the grid is a numerical failure (exit 3), not silent loss
sed -e 's#"max": \[0.4, 0.2\]}#"max": [0.4, 0.2], "velocity": [40, 0]}#' -e 's#"xmax": "sliding"#"xmax": "free"#' \
    -e 's#"save_state": ".*"#"name": "escape"#' -e 's#"name": "small",##' "$tmp/small.json" > "$tmp/escape.json"
expect 3 "particle leaving the grid" -- "$exe" "$tmp/escape.json" --output "$tmp/escape" --quiet
contains "left the grid" "particle leaving the grid"

# a 3D case runs end to end
cat > "$tmp/cube.json" <<'JSON'
{
  "name": "cube",
  "domain": {"nx": 6, "ny": 6, "nz": 6, "dx": 0.1,
             "boundaries": {"zmin": "fixed", "xmin": "sliding", "ymin": "sliding"}},
  "particles": {"ppc": 2},
  "materials": [{"name": "soil", "type": "linear_elastic", "E": 1e6, "nu": 0.25, "rho": 2000}],
  "bodies": [{"material": "soil", "min": [0, 0, 0], "max": [0.3, 0.3, 0.3]}],
  "gravity": [0, 0, -9.81],
  "solver": {"scheme": "USL", "shape_function": "linear"},
  "time": {"tend": 0.02},
  "output": {"interval": 0.01, "grid": true}
}
JSON
expect 0 "3D run" -- "$exe" "$tmp/cube.json" --output "$tmp/cube" --quiet
[ -s "$tmp/cube/cube.xdmf" ] && [ -s "$tmp/cube/particles_000002.h5" ] && ok || bad "3D run outputs"

# STL terrain contact: the run writes the terrain beside the particles; bad STL input refused
cp tests/cli/cases/terrain_block.json "$tmp/floor.json"
expect 0 "run with an STL terrain" -- "$exe" "$tmp/floor.json" --output "$tmp/floor" --quiet
[ -s "$tmp/floor/terrain.xdmf" ] && [ -s "$tmp/floor/terrain.h5" ] && ok \
    || bad "the terrain is written beside the particles"
printf 'solid x\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n' > "$tmp/cut.stl"
sed "s#tests/data/stl/floor_2000.stl#$tmp/cut.stl#" "$tmp/floor.json" > "$tmp/cut.json"
expect 2 "truncated STL terrain" -- "$exe" "$tmp/cut.json" --output "$tmp/cut" --quiet
contains "contact.file" "truncated STL terrain: the message names the key"
sed 's#"mu": 0.2, "file"#"mu": 0.2, "offset": [0, 100, 0], "file"#' "$tmp/floor.json" > "$tmp/far.json"
expect 2 "STL terrain far from the domain" -- "$exe" "$tmp/far.json" --output "$tmp/far" --quiet
contains "does not come within reach of the domain" "STL terrain far from the domain: why"

# a geostatic start (initial_stress k0) reports whether the ground is at rest: a layered
# column is; with a K0 beyond the sand's strength (0.2 < (1 - sin 30)/(1 + sin 30)) it is not
cat > "$tmp/k0.json" <<'JSON'
{
  "name": "k0",
  "domain": {"nx": 4, "ny": 20, "dx": 0.5,
             "boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}},
  "materials": [{"name": "clay", "type": "linear_elastic", "E": 2e7, "nu": 0.3, "rho": 1800},
                {"name": "sand", "type": "mohr_coulomb", "E": 4e7, "nu": 0.3, "rho": 2000,
                 "phi": 30, "c": 0, "psi": 0}],
  "bodies": [{"material": "sand", "min": [0, 0], "max": [2, 4]},
             {"material": "clay", "polygon": [[0, 4], [2, 4], [2, 8], [0, 8]]}],
  "gravity": [0, -9.81],
  "initial_stress": {"type": "k0"},
  "time": {"tend": 0.2, "cfl": 0.5},
  "output": {"interval": 0.1}
}
JSON
expect 0 "K0 start" -- "$exe" "$tmp/k0.json" --output "$tmp/k0"
contains "the ground starts at rest (in equilibrium)" "K0 start: reported at rest"
sed 's#{"type": "k0"}#{"type": "k0", "k0": 0.2}#' "$tmp/k0.json" > "$tmp/k0_low.json"
expect 0 "K0 start beyond the strength" -- "$exe" "$tmp/k0_low.json" --output "$tmp/k0_low"
contains "the ground is not in equilibrium at the start" "K0 beyond the strength: reported"

# a region of prescribed_motion: its reaction and displacement are history.csv columns, and
# the run says when it has moved more than half a cell (its box takes the next row of nodes)
cat > "$tmp/plate.json" <<'JSON'
{
  "name": "plate",
  "domain": {"nx": 4, "ny": 10, "dx": 0.25,
             "boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}},
  "materials": [{"name": "m", "type": "linear_elastic", "E": 1e7, "nu": 0.3, "rho": 2000}],
  "bodies": [{"material": "m", "min": [0, 0], "max": [1, 2]}],
  "prescribed_motion": [{"name": "plate", "min": [0, 1.9], "max": [1, 2.1],
                         "velocity": [0, -0.5], "components": ["y"],
                         "time_function": {"type": "ramp", "duration": 0.05}}],
  "damping": {"type": "local", "value": 0.1},
  "time": {"tend": 0.3, "cfl": 0.5},
  "output": {"interval": 0.1}
}
JSON
expect 0 "prescribed motion" -- "$exe" "$tmp/plate.json" --output "$tmp/plate"
contains 'prescribed_motion[1] "plate" has moved 0.12' "prescribed motion: half a cell noted"
head -1 "$tmp/plate/history.csv" | grep -q ",reaction_plate_x,reaction_plate_y,displacement_plate_x,displacement_plate_y$" \
    && ok || bad "prescribed motion: history.csv columns of the region"

# ParaView's readers on the outputs: tests/cli/test_paraview.sh

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

# Shared by the command-line test scripts (sourced, not run): the pass/fail counters and the
# checks on a command's exit code and output. The script sets `tmp` (its scratch folder) and
# `label` (the prefix of its failure lines) before sourcing this file.
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL [$label] $1"; }

# expect CODE DESCRIPTION -- command...   (stdout+stderr in $tmp/out)
expect() {
    local code=$1 what=$2
    shift 3
    "$@" > "$tmp/out" 2>&1
    local rc=$?
    if [ "$rc" -eq "$code" ]; then ok; else bad "$what: exit code $rc, expected $code"; cat "$tmp/out"; fi
    # one clear message, never a crash report
    if grep -qE "Backtrace|Error termination|Segmentation|SIGSEGV" "$tmp/out"; then
        bad "$what: output holds a crash report"; cat "$tmp/out"
    else
        ok
    fi
}

# contains TEXT DESCRIPTION: $tmp/out holds TEXT
contains() {
    if grep -qF -- "$1" "$tmp/out"; then ok; else bad "$2: output lacks '$1'"; cat "$tmp/out"; fi
}

# need_python MODULE...: sets `python` to the tests' interpreter ($MPM_PYTHON, which CTest sets
# from the one found at configure time; .venv/bin/python when run by hand) and checks that it
# imports the modules. When it cannot, the script ends with exit code 77, which CTest reports
# as skipped, and says why; with MPM_STRICT_TESTS=1 (make test) that is a failure instead, so
# a run of the whole suite never passes by skipping.
need_python() {
    python=${MPM_PYTHON:-.venv/bin/python}
    local why="" modules
    modules=$(IFS=,; echo "$*")
    if [ -z "$python" ] || ! command -v "$python" > /dev/null 2>&1; then
        why="no Python interpreter (MPM_PYTHON='$python')"
    elif ! "$python" -c "import $modules" > /dev/null 2>&1; then
        why="$python cannot import $*"
    fi
    [ -z "$why" ] && return 0
    if [ "${MPM_STRICT_TESTS:-0}" = 1 ]; then
        echo "FAIL [$label] $why (make deps sets up .venv)"
        exit 1
    fi
    echo "SKIP [$label] $why: make deps sets up .venv, or configure with" \
        "-DMPM_TEST_PYTHON=/path/to/python that has $*"
    exit 77
}

# need_tool PROGRAM WHAT: the program is on PATH, or the script is skipped (exit 77) saying
# that WHAT is not checked; with MPM_STRICT_TESTS=1 (make test) that is a failure instead.
need_tool() {
    command -v "$1" > /dev/null 2>&1 && return 0
    if [ "${MPM_STRICT_TESTS:-0}" = 1 ]; then
        echo "FAIL [$label] $1 not found: $2 (make deps-test installs it)"
        exit 1
    fi
    echo "SKIP [$label] $1 not found: $2 is not checked (make deps-test installs it)"
    exit 77
}

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

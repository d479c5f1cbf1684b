#!/usr/bin/env bash
# Hostile input: every case in tests/bad_inputs/ must be refused with exit code 2 and exactly
# one message ("mpm_geo: error: ..." naming the case file), never a crash, a backtrace or a
# hang, and must write no output. So must the cases that cannot be committed: a FIFO, a
# folder, devices, a /proc file, a sparse 2 GiB file, 10 000 nested arrays.
# Usage: tests/cli/test_bad_inputs.sh path/to/mpm_geo   (run from the repository root)
set -u
exe=$(realpath "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0

# refused CASE [TEXT]: exit code 2 within 60 s, one message naming CASE (and holding TEXT),
# no crash report, no output folder
refused() {
    local case=$1 text=${2:-} name problem messages rc
    name=$(basename "$case")
    timeout -k 5 60 "$exe" "$case" --output "$tmp/out-$name" > "$tmp/stdout" 2> "$tmp/stderr" \
        < /dev/null
    rc=$?
    messages=$(grep -c "^mpm_geo: error:" "$tmp/stderr")
    problem=""
    [ "$rc" -eq 2 ] || problem="exit code $rc, expected 2"
    [ "$messages" -eq 1 ] || problem="$problem; $messages error messages, expected 1"
    grep -qF -- "$case" "$tmp/stderr" || problem="$problem; the message does not name the file"
    if [ -n "$text" ] && ! grep -qF -- "$text" "$tmp/stderr"; then
        problem="$problem; the message does not say '$text'"
    fi
    if grep -qE "Backtrace|Error termination|Segmentation|SIGSEGV|ERROR STOP" "$tmp/stderr"; then
        problem="$problem; crash report"
    fi
    [ -e "$tmp/out-$name" ] && problem="$problem; an output folder was written"
    if [ -z "$problem" ]; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
        echo "FAIL [bad input] $name: ${problem#; }"
        sed 's/^/    /' "$tmp/stderr" | head -5
    fi
}

for case in tests/bad_inputs/*.json; do
    refused "$case"
done
ncommitted=$passed

# files that are not regular files are refused before they are opened (a FIFO would block)
mkfifo "$tmp/fifo.json"
refused "$tmp/fifo.json" "not a regular file (a FIFO)"
mkdir "$tmp/folder.json"
refused "$tmp/folder.json" "not a regular file (a folder)"
refused /dev/zero "not a regular file (a character device)"
refused /dev/urandom "not a regular file (a character device)"
# a file whose size reads as 0 but that holds text is read, and is not JSON
refused /proc/self/status "not a JSON text"
# too large: a sparse file of 2 GiB, and one byte above the limit
truncate -s 2G "$tmp/huge.json"
refused "$tmp/huge.json" "file too large: 2147483648 bytes, at most 67108864"
truncate -s $((64 * 1024 * 1024 + 1)) "$tmp/limit.json"
refused "$tmp/limit.json" "file too large: 67108865 bytes, at most 67108864"
# nesting: 10 000 arrays are refused for their depth; 1000, cJSON's limit, parse
head -c 10000 /dev/zero | tr '\0' '[' > "$tmp/deep.json"
head -c 10000 /dev/zero | tr '\0' ']' >> "$tmp/deep.json"
refused "$tmp/deep.json" "nested deeper than 1000 levels"
head -c 1000 /dev/zero | tr '\0' '[' > "$tmp/deep1000.json"
head -c 1000 /dev/zero | tr '\0' ']' >> "$tmp/deep1000.json"
refused "$tmp/deep1000.json" "the top level must be a JSON object"

echo "$passed passed, $failed failed"
[ "$ncommitted" -ge 40 ] || { echo "FAIL [bad input] fewer than 40 cases"; exit 1; }
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# The API pages of mpm-geo (make docs): FORD reads the doc comments of src/ and app/ (docs/ford.md
# is the project file) and writes build/docs/index.html. The developer pages (docs/architecture.md,
# docs/testing.md) are copied in as FORD pages. Any FORD warning (a doc comment FORD misreads,
# e.g. one that starts with "word:" and is taken for metadata) fails the build, so the pages
# say what the comments say.
set -euo pipefail
cd "$(dirname "$0")/.."
python=.venv/bin/python
[ -x "$python" ] || bash scripts/install_deps.sh
if ! .venv/bin/ford --version > /dev/null 2>&1; then
    echo "installing FORD into .venv (docs/requirements-docs.txt)"
    "$python" -m pip install -q -r docs/requirements-docs.txt
fi
pages=build/ford-pages
rm -rf "$pages"
mkdir -p "$pages"
cp docs/ford-pages/index.md "$pages/index.md"
for page in architecture testing; do
    title=$(sed -n '1s/^# *//p' "docs/$page.md")
    { printf -- '---\ntitle: %s\n---\n\n' "$title"; sed '1d' "docs/$page.md"; } > "$pages/$page.md"
done
log=$(mktemp)
trap 'rm -f "$log"' EXIT
.venv/bin/ford docs/ford.md 2>&1 | tee "$log" | grep -v -E '^\s*(Parsing|Processing|Writing|Creating|Correlating|\.\.\.done)' || true
if grep -q -i 'warning' "$log"; then
    echo "make docs: FORD warned (above); fix the doc comments it names" >&2
    exit 1
fi
[ -f build/docs/index.html ] || { echo "make docs: build/docs/index.html was not written" >&2; exit 1; }
echo "API pages: build/docs/index.html"

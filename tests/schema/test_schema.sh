#!/usr/bin/env bash
# CTest's case_schema: tests/schema/check_schema.py with the tests' Python (jsonschema), or
# skipped with the reason when that Python lacks it (see need_python in tests/cli/lib.sh).
# Usage: tests/schema/test_schema.sh build/print_case_keys build/mpm_geo   (from the repository root)
set -u
label=case_schema
# shellcheck source=tests/cli/lib.sh
. tests/cli/lib.sh
need_python jsonschema
exec "$python" tests/schema/check_schema.py --keys-program "$1" --exe "$2"

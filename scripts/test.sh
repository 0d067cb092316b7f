#!/usr/bin/env bash
# The README's test command: installs what is missing, builds (Release) and
# runs the whole test suite with ctest. Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/bootstrap.sh
ctest --test-dir "${TT_BUILD_DIR:-build}" --output-on-failure -j2 "$@"

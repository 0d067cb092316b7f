#!/usr/bin/env bash
# The README's test command: installs what is missing (the build's packages
# and, for the Python package's tests, Debian's numpy and pytest), builds
# (Release) and runs the whole test suite with ctest: the C tests, the
# install + consumer test and pytest. Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/python-deps.sh
scripts/bootstrap.sh
ctest --test-dir "${TT_BUILD_DIR:-build}" --output-on-failure -j2 "$@"

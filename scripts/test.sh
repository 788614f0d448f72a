#!/usr/bin/env bash
# Builds everything (installing what is missing) and runs all tests through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure -j"${DVISPH_TEST_JOBS:-1}"

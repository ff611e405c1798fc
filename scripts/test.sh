#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs every test with ctest. Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR="${RAMTK_BUILD_DIR:-build}"
ctest --test-dir "${BUILD_DIR}" --output-on-failure -j "${RAMTK_JOBS:-$(nproc)}" "$@"

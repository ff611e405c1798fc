#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer over a subset of the suites: core, kinematics and
# thermal by default (what CI runs, a few minutes; docs/reliability.md), or the suites named in
# RAMTK_ASAN_SUITES (e.g. "core_tests kinematics_tests thermal_tests tcf_tests"). Builds into
# build-asan (only those targets, optimised without debug info to keep CI short; frame pointers
# kept for the reports' stacks), then runs each suite; any sanitizer report fails the run. The whole suite under the
# sanitizers: `cmake -S . -B build-asan -DRAMTK_SANITIZE=ON ... && cmake --build build-asan &&
# ctest --test-dir build-asan` (about an hour on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
DIR="${RAMTK_ASAN_DIR:-build-asan}"
read -r -a SUITES <<<"${RAMTK_ASAN_SUITES:-core_tests kinematics_tests thermal_tests}"
cmake -S . -B "$DIR" -G Ninja -DRAMTK_SANITIZE=ON -DCMAKE_BUILD_TYPE=Release -DRAMTK_BUILD_BENCH=OFF \
  -DRAMTK_BUILD_PYTHON=OFF >/dev/null
cmake --build "$DIR" -j "${RAMTK_JOBS:-$(nproc)}" --target "${SUITES[@]}"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for s in "${SUITES[@]}"; do
  bin=$(find "$DIR/tests" -name "$s" -type f -perm -u+x | head -1)
  echo "[sanitize] $s"
  (cd "$(dirname "$bin")" && "./$s" --gtest_brief=1)
done
echo "[sanitize] ${#SUITES[@]} suites clean under ASan + UBSan"

#!/usr/bin/env bash
# Builds the fuzz targets with clang and runs each for RUNS executions (default 10^6), seeded from
# the project's own files; new corpus entries go to build-fuzz/corpus/<target>, crash reproducers
# to fuzz/crashes/ (keep them: tests/tools replays them). Usage: bash fuzz/run.sh [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-1000000}
CC=clang CXX=clang++ cmake -S fuzz -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-fuzz
mkdir -p fuzz/crashes
seed() {  # target, seed files...
  local dir=build-fuzz/corpus/$1
  mkdir -p "$dir"
  shift
  for f in "$@"; do cp "$f" "$dir/" 2>/dev/null || true; done
}
seed fuzz_csv fuzz/seeds/*.csv tests/thermal/data/*.csv datasets/tcf/*.csv datasets/thermal/*.csv
seed fuzz_measurements fuzz/seeds/*.csv tests/thermal/data/*.csv
seed fuzz_robot_yaml datasets/robots/*.yaml
seed fuzz_tracker fuzz/seeds/tracker_*.csv fuzz/seeds/*.csv docs/examples/ipa_tmac_*.yaml
seed fuzz_manifest datasets/scan_default/manifest.json datasets/vision/*.json
seed fuzz_laser_log fuzz/seeds/laser_log.csv
seed fuzz_tcf_json fuzz/seeds/tcf_*.json
seed fuzz_ply fuzz/seeds/*.ply
seed fuzz_stereo_calibration datasets/scan_default/calibration.yml fuzz/seeds/*.yml fuzz/seeds/calibration.json \
  fuzz/seeds/calibration.xml
seed fuzz_image fuzz/seeds/*.png fuzz/seeds/*.bmp
for t in fuzz_csv fuzz_measurements fuzz_robot_yaml fuzz_tracker fuzz_manifest fuzz_laser_log fuzz_tcf_json fuzz_ply \
         fuzz_stereo_calibration fuzz_image; do
  # The motion JSON seed is ~4.5 KiB: room for it; the others fit in 1 KiB.
  len=1024
  [ "$t" = fuzz_tcf_json ] && len=6144
  [ "$t" = fuzz_stereo_calibration ] && len=4096  # a calibration file is ~2-3 KiB
  [ "$t" = fuzz_image ] && len=2048  # the BMP seed is 1.3 KiB
  echo "== $t: $RUNS runs"
  # Inputs up to 1 KiB: every format's structure fits, and runs stay fast (~5000/s for the CSV
  # parser under ASan + UBSan on one core).
  build-fuzz/$t -runs="$RUNS" -max_len=$len -timeout=10 -artifact_prefix=fuzz/crashes/$t- \
    -print_final_stats=1 build-fuzz/corpus/$t >build-fuzz/$t.log 2>&1 || echo "$t: FINDING, see build-fuzz/$t.log"
  grep -E "^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss|==.*ERROR|SUMMARY)" build-fuzz/$t.log || true
done

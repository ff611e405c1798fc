#!/usr/bin/env bash
# Inputs shared by the table-driven bad-input cases (bad_input_cases.tsv): made once per ctest run.
#   bad_input_fixture.sh RAMTK DATASETS FIXTURE_DIR
set -eu
R=$1 D=$2 FX=$3
rm -rf "$FX"
mkdir -p "$FX"
cd "$FX"
KR=$D/robots/kuka_kr150_r3100.yaml
"$R" simulate sensor-robot --robot "$KR" --output m.csv --truth m_truth.json >/dev/null
"$R" simulate thermal --robot "$KR" --cycles 6 --out th >/dev/null
mkdir tcf && "$R" simulate tcf --out-dir tcf --seed 3 >/dev/null
"$R" simulate hand-eye --robot "$KR" --output he.csv --truth he_truth.json >/dev/null
cp -r "$D/scan_default" set
printf 'x,y,z\n1,2,3\n4,5,6\n7,8,10\n2,2,2\n' > pts.csv
# Checksums of every input: each case must leave them unchanged.
find . -type f -print0 | sort -z | xargs -0 md5sum > ../bad_input_fixture.md5
echo ok

#!/usr/bin/env bash
# Bad input and interruption, the way a hostile or unlucky user meets ramtk (issue 17). Each case
# asserts the exit code, that stderr names the culprit, that no output or temporary remains and
# that the inputs are unchanged.
#
#   bad_input.sh CASE RAMTK DATASETS_DIR WORK_DIR TOOLS_TEST_DIR
set -u
CASE=$1 RAMTK=$2 DATASETS=$3 WORK=$4/$1 HERE=$5
KR150=$DATASETS/robots/kuka_kr150_r3100.yaml

fail() { echo "FAIL [$CASE]: $*" >&2; exit 1; }
# run EXPECTED_CODE STDERR_REGEX -- command...
run() {
  local want=$1 pattern=$2
  shift 3
  "$@" >"$WORK/stdout" 2>"$WORK/stderr"
  local got=$?
  [ "$got" = "$want" ] || fail "exit $got, expected $want: $* ; stderr: $(head -c 600 "$WORK/stderr")"
  if [ -n "$pattern" ]; then
    grep -Eq -- "$pattern" "$WORK/stderr" || fail "stderr does not match '$pattern': $(head -c 600 "$WORK/stderr")"
  fi
  grep -q "terminate called\|Check failed\|Segmentation\|Aborted" "$WORK/stderr" && fail "crash text on stderr"
  return 0
}
absent() { [ ! -e "$1" ] || fail "$1 exists but must not"; }
no_temporaries() {
  local left
  left=$(find "$1" \( -name '*.partial-*' -o -name '*.tmp*' -o -name '*.old-*' \) 2>/dev/null | head -3)
  [ -z "$left" ] || fail "temporaries left behind: $left"
}
same() { cmp -s "$1" "$2" || fail "$1 changed"; }
# interrupted GLOB DELAY -- command...: runs the command in the background, waits until GLOB
# matches (its staging folder), lets it run DELAY s more, sends SIGINT and expects exit 130.
interrupted() {
  local glob=$1 delay=$2
  shift 3
  "$@" >/dev/null 2>&1 &
  local pid=$!
  for _ in $(seq 1 600); do
    compgen -G "$glob" >/dev/null && break
    sleep 0.05
  done
  compgen -G "$glob" >/dev/null || fail "$glob never appeared"
  sleep "$delay"
  kill -INT $pid
  wait $pid
  local code=$?
  [ "$code" = 130 ] || fail "exit $code after SIGINT, expected 130"
}

rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK" || exit 1

case $CASE in
  image_header_claims_a_terapixel)
    # A 68-byte PNG whose header says 10^6 x 10^6: refused from the header, nothing allocated.
    cp -r "$DATASETS/scan_default" set
    python3 - <<'EOF' || fail "python3 needed"
import json
m = json.load(open('set/manifest.json'))
m['cameras']['left'][0] = 'huge.png'
json.dump(m, open('set/huge.json', 'w'))
EOF
    cp "$HERE/huge_header.png" set/huge.png
    run 1 "huge.png: image header claims 1000000 x 1000000" -- "$RAMTK" decode set/huge.json --out out
    absent out
    run 1 "huge.png: image header claims" -- "$RAMTK" scan set/huge.json --out out2
    absent out2
    ;;
  projector_of_two_billion_pixels)
    run 1 "at most 16384 px \(kMaxProjectorSide\)" -- "$RAMTK" patterns --width 2000000000 --height 2000000000 --cycles 16 --out p
    absent p
    ;;
  scan_output_is_the_input_set)
    cp -r "$DATASETS/scan_default" set
    cp set/manifest.json manifest.keep
    run 1 "field '--out': contains the input" -- "$RAMTK" scan set/manifest.json --out set --force
    same set/manifest.json manifest.keep
    [ -d set/left ] || fail "input images deleted"
    run 1 "contains the input" -- "$RAMTK" decode set/manifest.json --out set/ --force
    same set/manifest.json manifest.keep
    no_temporaries .
    ;;
  calib_output_is_the_measurement_file)
    "$RAMTK" simulate sensor-robot --robot "$KR150" --output m.csv --truth t.json >/dev/null || fail "simulate"
    cp m.csv m.keep
    run 1 "field '--output': is the input" -- "$RAMTK" calib sensor-robot --robot "$KR150" --measurements m.csv --output ./m.csv
    same m.csv m.keep
    ;;
  thermal_outputs_are_inputs_or_each_other)
    "$RAMTK" simulate thermal --robot "$KR150" --cycles 6 --out th >/dev/null || fail "simulate thermal"
    cp th/ball.csv ball.keep
    IN=(--robot "$KR150" --setup th/setup.json --ball th/ball.csv)
    run 1 "field '--out': is the input" -- "$RAMTK" thermal identify "${IN[@]}" --params d4,a2 --out th/ball.csv
    same th/ball.csv ball.keep
    run 1 "each output needs its own path" -- "$RAMTK" thermal screen "${IN[@]}" --monitoring th/monitoring.csv --json x.json --series x.json
    absent x.json
    run 1 "output exists and is not an empty folder" -- "$RAMTK" simulate thermal --robot "$KR150" --cycles 6 --out th
    same th/ball.csv ball.keep
    ;;
  tcf_solve_output_is_the_log)
    "$RAMTK" simulate tcf --out-dir . --seed 2 >/dev/null || fail "simulate tcf"
    cp laser_log.csv log.keep
    run 1 "field '--out': is the input" -- "$RAMTK" tcf solve --log laser_log.csv --motion motion.json --sensor sensor.json --out laser_log.csv
    same laser_log.csv log.keep
    ;;
  simulated_sensor_file_is_deterministic)
    # Uninitialised memory showed as values like 1e180 that changed from run to run.
    mkdir a b
    "$RAMTK" simulate tcf --out-dir a --seed 4 >/dev/null || fail "simulate tcf a"
    "$RAMTK" simulate tcf --out-dir b --seed 4 >/dev/null || fail "simulate tcf b"
    for f in sensor.json truth.json motion.json laser_log.csv; do same a/$f b/$f; done
    grep -Eq "e[+-][0-9]{3}" a/sensor.json && fail "sensor.json holds a value of magnitude 1e100 or beyond"
    no_temporaries .
    ;;
  measurement_value_1e308)
    "$RAMTK" simulate sensor-robot --robot "$KR150" --output m.csv --truth t.json >/dev/null || fail "simulate"
    awk -F, 'BEGIN{OFS=","} NR==2{$10="1e308"} {print}' m.csv >one.csv
    awk -F, 'BEGIN{OFS=","} NR>1{$10=$11=$12="1e308"} {print}' m.csv >all.csv
    run 1 "one.csv:2: field 'x': value 1e308 is beyond the plausible range.*kMaxAbsPositionMm" -- "$RAMTK" calib sensor-robot --robot "$KR150" --measurements one.csv --output r1.json
    run 1 "all.csv:2: field 'x'" -- "$RAMTK" calib sensor-robot --robot "$KR150" --measurements all.csv --output r2.json
    absent r1.json
    absent r2.json
    ;;
  measurement_file_with_byte_order_mark)
    "$RAMTK" simulate sensor-robot --robot "$KR150" --output m.csv --truth t.json >/dev/null || fail "simulate"
    printf '\xEF\xBB\xBF' >bom.csv
    cat m.csv >>bom.csv
    run 0 "" -- "$RAMTK" calib sensor-robot --robot "$KR150" --measurements bom.csv --output r.json
    [ -s r.json ] || fail "no result"
    ;;
  phase_origin_1e308)
    cp -r "$DATASETS/scan_default" set
    sed 's/"phase_at_origin_deg": *[-0-9.e]*/"phase_at_origin_deg": 1e308/' set/manifest.json >set/bad.json
    grep -q 1e308 set/bad.json || fail "test set-up: no phase_at_origin_deg in the manifest"
    run 1 "phase_at_origin_deg.*within \[-360, 360\]" -- "$RAMTK" decode set/bad.json --out out
    absent out
    ;;
  zero_stereo_baseline)
    cp -r "$DATASETS/scan_default" set
    python3 - <<'EOF' || fail "python3 needed"
import re
t = open('set/calibration.yml').read()
t = re.sub(r'(T: !!opencv-matrix[^\]]*data: \[)[^\]]*\]', r'\1 0., 0., 0. ]', t, flags=re.S)
open('set/calibration.yml', 'w').write(t)
EOF
    run 1 "calibration.yml.*stereo baseline \|T\| = 0" -- "$RAMTK" scan set/manifest.json --out out
    absent out
    ;;
  interrupted_simulation_keeps_the_old_result)
    "$RAMTK" simulate fringe --out sim --no-noise >/dev/null || fail "first simulation"
    cp sim/manifest.json manifest.keep
    interrupted "sim.partial-*" 0.3 -- "$RAMTK" simulate fringe --out sim --force --supersampling 16
    no_temporaries .
    same sim/manifest.json manifest.keep
    [ -d sim/left ] || fail "old result damaged"
    ;;
  interrupted_campaign_leaves_no_folder)
    # The campaign twin is staged as a whole: interrupted while it renders, nothing remains.
    interrupted "camp.partial-*/sets" 0.2 -- "$RAMTK" simulate campaign --robot "$KR150" --out camp --cycles 2 --poses 5 --jobs 1 -q
    no_temporaries .
    absent camp
    ;;
  interrupted_batch_is_resumed)
    # SIGINT in the middle of a batch: finished set folders stay, no results.csv, no lock; then
    # --resume keeps those folders as they are and scans only the rest.
    for _ in 1 2 3 4 5 6; do echo "$DATASETS/scan_default/manifest.json"; done >b.txt
    interrupted "s/001_scan_default" 0.05 -- "$RAMTK" scan --batch b.txt --out s --roi auto --jobs 1 -q
    no_temporaries .
    absent s/results.csv
    [ -z "$(find . -name '*.lock')" ] || fail "lock file left"
    kept=$(stat -c %i s/000_scan_default)
    "$RAMTK" scan --batch b.txt --out s --roi auto -q >/dev/null 2>err.txt && fail "a re-run without --resume was accepted"
    grep -q -- "--resume" err.txt || fail "wrong message: $(cat err.txt)"
    "$RAMTK" scan --batch b.txt --out s --roi auto --jobs 1 -q --resume >/dev/null || fail "--resume failed"
    [ "$(grep -c ',ok,' s/results.csv)" = 6 ] || fail "expected 6 ok rows: $(cat s/results.csv)"
    [ "$(stat -c %i s/000_scan_default)" = "$kept" ] || fail "a finished set was scanned again"
    no_temporaries .
    ;;
  *)
    fail "unknown case"
    ;;
esac
echo "ok [$CASE]"

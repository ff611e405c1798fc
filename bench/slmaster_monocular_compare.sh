#!/bin/sh
# ramtk's camera–projector scan beside SLMaster's monocular path on SLMaster's own monocular
# capture (../shared/data/slmaster-monocular): whole-process wall time of each (best of REPS runs),
# point counts, cloud-to-cloud distance against ramtk's predicted sigma.
# usage (from the checkout, after cmake --build build --target ramtk vision_monocular_peer and
#        sh bench/peers/slmaster_monocular/build.sh GITDIR):
#   sh bench/slmaster_monocular_compare.sh [BUILD_DIR] [PEER_DRIVER] [REPS]
set -e
BUILD=${1:-build}
PEER=${2:-${TMPDIR:-/tmp}/peer-slm-mono/driver}
REPS=${3:-5}
DATA=${RAMTK_SHARED_DIR:-../shared}/data/slmaster-monocular
OUT=${TMPDIR:-/tmp}/slm-mono-compare
mkdir -p "$OUT"
best() {  # best wall time (s) of REPS runs of "$@"
  b=""
  i=0
  while [ $i -lt "$REPS" ]; do
    s=$(date +%s.%N); "$@" > "$OUT/last.txt" 2>&1 || true; e=$(date +%s.%N)
    t=$(echo "$e - $s" | bc)
    if [ -z "$b" ] || [ "$(echo "$t < $b" | bc)" = 1 ]; then b=$t; fi
    i=$((i + 1))
  done
  echo "$b"
}
t_ramtk=$(best "$BUILD/tools/ramtk" scan datasets/vision/slmaster_monocular.json --out "$OUT/ramtk" --force -q)
cat "$OUT/last.txt"
t_peer=$(best "$PEER" --data "$DATA" --out "$OUT/slmaster.ply")
cat "$OUT/last.txt"
echo "whole process (best of $REPS): ramtk $t_ramtk s, SLMaster $t_peer s, SLMaster / ramtk $(echo "scale=2; $t_peer / $t_ramtk" | bc)"
"$BUILD/bench/vision_monocular_peer" "$OUT/ramtk/cloud.ply" "$OUT/slmaster.ply"

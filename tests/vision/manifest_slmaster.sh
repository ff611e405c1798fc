#!/bin/sh
# `ramtk manifest` on the SLMaster binocular capture scans to the same cloud as the hand-written
# datasets/vision/slmaster_binocular.json (cmp), and so does a manifest holding globs (natural
# order: 0, 1, 2, ..., 10, not 0, 1, 10, 11). Exit 77 (skipped) without the shared data.
#   manifest_slmaster.sh RAMTK SHARED_DIR HANDWRITTEN_MANIFEST WORK_DIR
set -e
RAMTK=$1 DATA=$2/data/slmaster-binocular HAND=$3 WORK=$4
if [ ! -d "$DATA/L" ]; then echo "skipped: $DATA is absent"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
"$RAMTK" manifest "$DATA" --sequence ps:12:64,cgc:7 --projector 1280x720 --calib "$DATA/caliInfo.yml" \
  --out "$WORK/manifest.json"
# A sequence one frame short is refused, naming the camera, and writes nothing.
if "$RAMTK" manifest "$DATA" --sequence ps:12:64,cgc:6 --projector 1280x720 --out "$WORK/never.json" 2> "$WORK/err.txt"; then
  echo "a wrong frame count was accepted"; exit 1
fi
grep -q "field '--left': 19 files match 'L/\*', the sequence ps:12:64,cgc:6 needs 18" "$WORK/err.txt" || { cat "$WORK/err.txt"; exit 1; }
[ ! -e "$WORK/never.json" ] || { echo "never.json written"; exit 1; }
# The same set with globs in the manifest.
sed -e '/"left": \[/,/\]/c\    "left": ["'"$DATA"'/L/*.bmp"],' -e '/"right": \[/,/\]/c\    "right": ["'"$DATA"'/R/*.bmp"]' \
  "$WORK/manifest.json" > "$WORK/glob_manifest.json"
grep -q '/L/\*.bmp' "$WORK/glob_manifest.json"
# The scan finds no sphere on this object (exit 3); all three must end alike.
scan() { rc=0; "$RAMTK" scan "$1" --out "$2" -q > "$2.log" 2>&1 || rc=$?; echo "$rc"; }
rc_generated=$(scan "$WORK/manifest.json" "$WORK/generated")
rc_globbed=$(scan "$WORK/glob_manifest.json" "$WORK/globbed")
rc_hand=$(scan "$HAND" "$WORK/handwritten")
[ "$rc_generated" = "$rc_hand" ] && [ "$rc_globbed" = "$rc_hand" ] || { echo "exit codes $rc_generated $rc_globbed $rc_hand"; exit 1; }
# The PLY header names the set it came from; everything else must be byte-identical.
strip_set() { grep -av '^comment frame left_camera; set ' "$1" > "$2"; }
strip_set "$WORK/handwritten/cloud.ply" "$WORK/handwritten.ply"
for run in generated globbed; do
  strip_set "$WORK/$run/cloud.ply" "$WORK/$run.ply"
  cmp "$WORK/$run.ply" "$WORK/handwritten.ply"
done
echo "same cloud from the written, the globbed and the hand-written manifest"

#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs the main job on the bundled default data.
# Until the vision pipeline (`ramtk scan`) exists, the main job is the kinematics demo: forward
# kinematics of the Kawasaki BX200L (thesis Table 2-1) at the controller pose (90,0,0,0,0,0),
# compared with the controller's own reading there, then an FK -> IK -> FK round trip.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
RAMTK="${RAMTK_BUILD_DIR:-build}/tools/ramtk"
"$RAMTK" fk --robot datasets/robots/kawasaki_bx200l.yaml --joints 90,0,0,0,0,0 \
  --measured 1675.749,-0.650,1918.024
echo
"$RAMTK" ik --robot datasets/robots/kuka_kr150_r3100.yaml --joints 10,-80,95,20,35,-40 \
  --seed 0,-90,90,0,0,0

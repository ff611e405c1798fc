#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs the main job on the bundled default data: `ramtk scan` of
# the simulated 38.1 mm ball (datasets/scan_default: decode both cameras, match, triangulate,
# fit the sphere), printing the centre and its error against the simulator's truth; then the
# kinematics demo (forward kinematics of the Kawasaki BX200L at the thesis's pose).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
RAMTK="${RAMTK_BUILD_DIR:-build}/tools/ramtk"
OUT="${TMPDIR:-/tmp}/ramtk_demo_scan"
"$RAMTK" scan datasets/scan_default/manifest.json --truth datasets/scan_default/truth/truth.json \
  --out "$OUT" --force --report
echo "open $OUT/report.html in a browser: the ball's points in 3D with the fitted sphere, residuals, depth"
echo
"$RAMTK" fk --robot datasets/robots/kawasaki_bx200l.yaml --joints 90,0,0,0,0,0 \
  --measured 1675.749,-0.650,1918.024

#!/usr/bin/env bash
# `ramtk scan --batch --shard K/N` + `ramtk merge` give the results of one process (issue 19):
# 12 sets, 4 shards run with the GNU parallel one-liner of docs/cluster.md (a plain loop if
# parallel is missing), merged, compared with a single run; then a missing and a duplicated shard.
#
#   shard_merge.sh RAMTK WORK_DIR
set -u
RAMTK=$1 WORK=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK" || exit 1

# Four different simulated sets (noise differs by seed), each listed three times: 12 sets.
for s in 1 2 3 4; do
  "$RAMTK" simulate fringe --out sim$s --seed $s --supersampling 1 -q >/dev/null 2>&1 ||
    "$RAMTK" simulate fringe --out sim$s --seed $s --supersampling 1 >/dev/null || fail "simulate $s"
done
: >batch.txt
for i in $(seq 1 12); do
  s=$(( (i - 1) % 4 + 1 ))
  mkdir -p set$i
  python3 - "$WORK/sim$s" "$WORK/set$i" <<'PY' || fail "manifest"
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
m = json.load(open(os.path.join(src, "manifest.json")))
m["calibration"] = os.path.join(src, m["calibration"])
for cam in m["cameras"]:
    m["cameras"][cam] = [os.path.join(src, f) for f in m["cameras"][cam]]
json.dump(m, open(os.path.join(dst, "manifest.json"), "w"), indent=1)
PY
  echo "set$i/manifest.json" >>batch.txt
done

"$RAMTK" scan --batch batch.txt --out single --jobs 1 -q >single.txt || fail "single run"
# -q: only the totals line on stdout, not the 12 result rows (they are in results.csv).
[ "$(wc -l <single.txt)" = 1 ] || fail "scan --batch -q printed $(wc -l <single.txt) lines"
grep -q "^scanned 12 sets" single.txt || fail "scan --batch -q did not print its totals"

if command -v parallel >/dev/null; then
  # The one-liner of docs/cluster.md.
  parallel -j 2 "$RAMTK" scan --batch batch.txt --out sharded --shard {}/4 -q ::: 1 2 3 4 >/dev/null || fail "parallel"
else
  echo "GNU parallel not installed: running the 4 shards in a loop"
  for k in 1 2 3 4; do "$RAMTK" scan --batch batch.txt --out sharded --shard $k/4 -q >/dev/null || fail "shard $k"; done
fi
"$RAMTK" merge --batch batch.txt --out sharded >/dev/null || fail "merge"

# Same rows: every column but the wall time (seconds) and the output folder's root.
strip() { python3 -c '
import sys
from csv import reader, writer
rows = list(reader(open(sys.argv[1])))
h = rows[0]
w = writer(sys.stdout, lineterminator="\n")
for r in rows:
    r[h.index("seconds")] = ""
    r[h.index("out_dir")] = r[h.index("out_dir")].replace(sys.argv[2], "ROOT")
    w.writerow(r)' "$1" "$2"; }
diff <(strip single/results.csv single) <(strip sharded/results.csv sharded) || fail "merged results differ"
[ "$(wc -l <sharded/results.csv)" = 13 ] || fail "expected 12 rows"
# Byte-identical science outputs per set.
for d in single/0*_set*; do
  name=$(basename "$d")
  for f in cloud.ply spheres.json; do cmp -s "$d/$f" "sharded/$name/$f" || fail "$name/$f differs"; done
done

# A missing shard and a duplicated one are refused, naming the problem.
mkdir broken && cp sharded/results.shard-*.csv broken/
rm broken/results.shard-3-of-4.csv
"$RAMTK" merge --batch batch.txt --out broken 2>err.txt && fail "merge accepted a missing shard"
grep -q "shard 3 of 4 has no results" err.txt || fail "wrong message: $(cat err.txt)"
cp sharded/results.shard-2-of-4.csv broken/results.shard-3-of-4.csv
"$RAMTK" merge --batch batch.txt --out broken 2>err.txt && fail "merge accepted a duplicated shard"
grep -q "missing from the shard results\|appears more often" err.txt || fail "wrong message: $(cat err.txt)"
echo ok

#!/usr/bin/env bash
# The Slurm job array of docs/cluster.md, run as printed there on a single-node Slurm started in
# a temporary folder (slurm_cluster.sh): 8 sets in 4 array tasks, merged by the dependent job of
# the doc's submit lines. The merged results must be those of one `scan --batch` process and of
# the doc's GNU parallel one-liner (every file of every set folder byte-identical; results.csv
# identical but for the wall-time column), and an `scontrol requeue` of one finished task must
# leave the merged results byte-identical. About 35 s on 2 cores. Exit 77 (ctest SKIP_RETURN_CODE) when Slurm or GNU
# parallel is missing or the daemons cannot start (no root, no sudo).
#
#   slurm_array.sh RAMTK CLUSTER_MD WORK_DIR
set -u
RAMTK=$(realpath "$1") DOC=$(realpath "$2") WORK=$3
HERE=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*" >&2; slurm_logs >&2; slurm_stop; exit 1; }
# RAMTK_REQUIRE_SLURM=1 (CI) turns a skip into a failure: there the scheduler must really run.
skip() {
  [ "${RAMTK_REQUIRE_SLURM:-0}" = 1 ] && { echo "FAIL (RAMTK_REQUIRE_SLURM=1): $*" >&2; exit 1; }
  echo "SKIP: $*"
  exit 77
}
. "$HERE/slurm_cluster.sh"
command -v parallel >/dev/null || skip "GNU parallel not installed (Debian: parallel)"
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK" || exit 1
# The doc's commands call `ramtk`: this build's.
PATH=$(cd "$(dirname "$RAMTK")" && pwd):$PATH
export PATH

# The fenced block after the line `<!-- ctest: NAME -->` in docs/cluster.md, as printed there.
doc_block() {
  awk -v marker="<!-- ctest: $1 -->" '
    $0 == marker { found = 1; next }
    found == 1 && /^```/ { found = 2; next }
    found == 2 && /^```/ { exit }
    found == 2 { print }' "$DOC"
}
for name in slurm-array slurm-submit parallel; do
  [ -n "$(doc_block $name)" ] || { echo "FAIL: docs/cluster.md has no block marked '<!-- ctest: $name -->'" >&2; exit 1; }
done

# Four simulated sets (noise differs by seed), each listed twice: 8 sets, enough for the doc's
# 8 GNU parallel shards and 4 array tasks.
mkdir sets
for s in 1 2 3 4; do
  "$RAMTK" simulate fringe --out sets/sim$s --seed $s --supersampling 1 -q >/dev/null || { echo "FAIL: simulate $s" >&2; exit 1; }
done
: >sets.txt
for i in $(seq 1 8); do echo "../sets/sim$(( (i - 1) % 4 + 1 ))/manifest.json" >>sets.txt; done
for d in single parallel slurm; do mkdir $d && cp sets.txt $d/; done

(cd single && ramtk scan --batch sets.txt --out scans --jobs 2 -q >/dev/null) || { echo "FAIL: single run" >&2; exit 1; }
(cd parallel && doc_block parallel | bash -e) >parallel/out.txt 2>&1 || { cat parallel/out.txt >&2; echo "FAIL: the GNU parallel lines" >&2; exit 1; }

slurm_start "$WORK/cluster" || skip "Slurm cannot start here"
trap 'slurm_stop' EXIT
cd slurm
doc_block slurm-array >scan_array.sh
mkdir logs
# The doc's submit lines as printed, with 4 array tasks instead of the script's 32 (a command-line
# --array overrides the #SBATCH line; the merge job is left alone).
{
  echo 'sbatch() { case " $* " in *" scan_array.sh "*) command sbatch --array=1-4 "$@" ;; *) command sbatch "$@" ;; esac; }'
  doc_block slurm-submit
} >submit.sh
bash -e submit.sh >submit.txt 2>&1 || fail "the doc's submit lines: $(cat submit.txt)"

# Waits until this cluster has no job pending or running (at most $1 s).
wait_idle() {
  local t
  for t in $(seq 1 $(( $1 * 2 ))); do
    [ -z "$(squeue -h 2>/dev/null)" ] && return 0
    sleep 0.5
  done
  squeue >&2
  return 1
}
wait_idle 120 || fail "the array and the merge did not finish in 120 s"
array=$(scontrol -o show job | sed -n 's/.*ArrayJobId=\([0-9]*\) .*/\1/p' | head -n 1)
[ -n "$array" ] || fail "no array job in scontrol"
states=$(scontrol -o show job | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort | uniq -c | tr -s ' ')
[ "$(echo "$states" | tr -d ' ')" = "5COMPLETED" ] || fail "jobs not all COMPLETED: $states"
[ -s scans/results.csv ] || fail "the merge job wrote no scans/results.csv"
for k in 1 2 3 4; do [ -s scans/results.shard-$k-of-4.csv ] || fail "array task $k wrote no shard file"; done

# Every file of every set folder byte-identical, results.csv identical but for `seconds`.
no_seconds() {
  python3 -c '
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
col = rows[0].index("seconds")
w = csv.writer(sys.stdout, lineterminator="\n")
for r in rows:
    r[col] = ""
    w.writerow(r)' "$1"
}
same_as() {  # same_as OTHER_DIR: scans/ here against OTHER_DIR/scans
  diff <(no_seconds scans/results.csv) <(no_seconds "$1/scans/results.csv") >&2 || return 1
  local f
  for f in $(cd scans && find . -path './*_sim*/*' -type f ! -name summary.json ! -name row.csv | sort); do
    cmp "scans/$f" "$1/scans/$f" >&2 || return 1
  done
  [ "$(cd scans && find . -path './*_sim*/*' -type f | wc -l)" = "$(cd "$1/scans" && find . -path './*_sim*/*' -type f | wc -l)" ] ||
    { echo "different file lists under scans/" >&2; return 1; }
}
[ "$(wc -l <scans/results.csv)" = 9 ] || fail "expected 8 rows in results.csv"
same_as ../single || fail "the Slurm array's results differ from one scan --batch process"
same_as ../parallel || fail "the Slurm array's results differ from the GNU parallel one-liner's"

# A finished task requeued (as Slurm does after a node failure or preemption) runs again into
# the same folder; the results, merged again, must not change by a byte.
cp scans/results.csv merged-first.csv
scontrol requeue "${array}_2" || fail "scontrol requeue ${array}_2"
sleep 1
wait_idle 60 || fail "the requeued task did not finish in 60 s"
task=$(scontrol -o show job "${array}_2")
echo "$task" | grep -q "JobState=COMPLETED" || fail "requeued task: $(echo "$task" | grep -o 'JobState=[A-Z_]*') ($(cat logs/scan-2.out))"
echo "$task" | grep -q "Restarts=1" || fail "task 2 did not run again: $(echo "$task" | grep -o 'Restarts=[0-9]*')"
ramtk merge --batch sets.txt --out scans --force >/dev/null || fail "merge after the requeue"
cmp merged-first.csv scans/results.csv || fail "results.csv changed after the requeue"
same_as ../single || fail "results differ from one process after the requeue"
echo ok

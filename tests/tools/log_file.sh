#!/usr/bin/env bash
# `ramtk --log-file FILE`: every message at debug and above goes into FILE as one line stamped
# with the UTC time (within the run's start and end) and its level, progress lines included, and
# the error that ends a command; stderr is byte-for-byte what it is without --log-file.
#
#   log_file.sh RAMTK WORK_DIR
set -u
RAMTK=$1 WORK=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK" || exit 1
"$RAMTK" simulate fringe --out sim --seed 1 --supersampling 1 -q >/dev/null || fail "simulate"
echo sim/manifest.json >sets.txt

start=$(date -u +%s)
"$RAMTK" scan --batch sets.txt --out plain -q >/dev/null 2>plain.err || fail "scan without --log-file"
"$RAMTK" --log-file run.log scan --batch sets.txt --out logged -q >/dev/null 2>logged.err || fail "scan with --log-file"
cmp plain.err logged.err || fail "stderr changed with --log-file"
# -v: the debug lines reach stderr as before and the file as well.
"$RAMTK" -v scan --batch sets.txt --out plain_v -q >/dev/null 2>plain_v.err || fail "scan -v"
"$RAMTK" -v --log-file run.log scan --batch sets.txt --out logged_v -q >/dev/null 2>logged_v.err || fail "scan -v --log-file"
grep -q '^ramtk: debug: ' plain_v.err || fail "scan -v printed no debug line on stderr"
diff <(grep -c '^ramtk: debug: ' plain_v.err) <(grep -c '^ramtk: debug: ' logged_v.err) || fail "-v stderr changed with --log-file"
grep -v '^ramtk: debug: ' plain_v.err >a.txt; grep -v '^ramtk: debug: ' logged_v.err >b.txt
cmp a.txt b.txt || fail "-v stderr changed with --log-file"
# Progress (no -q) into a pipe and into the file; an error at the end.
"$RAMTK" --log-file run.log scan --batch sets.txt --out progress >/dev/null 2>progress.err || fail "scan with progress"
"$RAMTK" --log-file run.log scan missing/manifest.json --out nothing >/dev/null 2>missing.err && fail "scan of a missing set succeeded"
"$RAMTK" scan missing/manifest.json --out nothing >/dev/null 2>missing_plain.err
cmp missing.err missing_plain.err || fail "the error on stderr changed with --log-file"
end=$(date -u +%s)

# Every line: stamp, level, message; the stamps within the runs.
python3 - "$start" "$end" run.log <<'PY' || fail "log file lines"
import re, sys, datetime
start, end, path = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
line_re = re.compile(r"^(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3})Z (debug|info|warning|error): (.+)$")
levels = {}
lines = open(path).read().splitlines()
assert lines, "empty log file"
for text in lines:
    m = line_re.match(text)
    assert m, "not a stamped, levelled line: " + text
    t = datetime.datetime.strptime(m.group(1), "%Y-%m-%dT%H:%M:%S.%f").replace(tzinfo=datetime.timezone.utc).timestamp()
    assert start - 1 <= t <= end + 1, "stamp outside the run: " + text
    levels.setdefault(m.group(2), []).append(m.group(3))
# Debug lines without -v (the file takes debug and above): the first --log-file run wrote some.
assert any(m.startswith("match ok:") for m in levels.get("debug", [])), "no debug line from the scan"
assert any(m.startswith("progress: scan 1/1 sets") for m in levels.get("info", [])), "no progress line"
assert levels.get("error", [""])[-1].startswith("missing/manifest.json"), "no error line naming the set"
print("log lines:", {k: len(v) for k, v in levels.items()})
PY
# A log file in a folder that does not exist: refused, the folder not created.
"$RAMTK" --log-file nofolder/run.log scan --batch sets.txt --out x -q >/dev/null 2>nofolder.err && fail "--log-file into a missing folder accepted"
grep -q "nofolder/run.log.*cannot open the log file" nofolder.err || fail "wrong message: $(cat nofolder.err)"
[ ! -e nofolder ] || fail "--log-file created a folder"
echo ok

#!/usr/bin/env bash
# Runs one row of bad_input_cases.tsv: NAME<TAB>EXIT<TAB>STDERR_REGEX<TAB>COMMAND. The command runs
# with bash in a fresh folder W, with R = the ramtk binary, D = datasets/, FX = the shared inputs
# (bad_input_fixture.sh). Checks: the exit code, stderr matches (and shows no crash), no temporary
# or partial output left in W or FX, and FX unchanged.
#   bad_input_case.sh TSV NAME RAMTK DATASETS FIXTURE_DIR WORK_ROOT
set -u
TSV=$1 NAME=$2
export R=$3 D=$4 FX=$5
W=$6/$NAME
fail() { echo "FAIL [$NAME]: $*" >&2; exit 1; }
line=$(awk -F'\t' -v n="$NAME" '$1 == n' "$TSV")
[ -n "$line" ] || fail "no such case"
want=$(printf '%s' "$line" | cut -f2)
pattern=$(printf '%s' "$line" | cut -f3)
cmd=$(printf '%s' "$line" | cut -f4-)
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1
export W
timeout 300 bash -c "$cmd" >stdout.txt 2>stderr.txt
got=$?
[ "$got" = "$want" ] || fail "exit $got, expected $want; command: $cmd; stderr: $(head -c 500 stderr.txt)"
if [ -n "$pattern" ]; then
  grep -Eq -- "$pattern" stderr.txt || fail "stderr does not match /$pattern/: $(head -c 500 stderr.txt)"
fi
grep -Eq "terminate called|Check failed|Segmentation|Aborted|AddressSanitizer|runtime error" stderr.txt && fail "crash: $(head -c 500 stderr.txt)"
left=$(find "$W" "$FX" \( -name '*.partial-*' -o -name '*.tmp[0-9]*' -o -name '*.old-*' -o -name '*.lock' \) 2>/dev/null | head -3)
[ -z "$left" ] || fail "temporaries left: $left"
(cd "$FX" && md5sum --quiet -c ../bad_input_fixture.md5) >/dev/null 2>&1 || fail "an input in the fixture changed"
echo "ok [$NAME]"

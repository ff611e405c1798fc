#!/usr/bin/python3
"""Re-run check of an output's provenance (docs/formats.md#provenance).

Runs a ramtk command into a fresh folder, reads the command line recorded in one of its outputs
(`provenance.command`), runs that command again into a second folder and compares every file of
the two folders. The run group is dropped first: the member `provenance.run` of JSON files, every
JSON member and CSV column named `seconds`, and the Markdown provenance line `- run: ...`. Text
files are compared after the second folder's path is written as the first's (the command line
names its output folder); every other byte must be equal.

  rerun_check.py --ramtk BIN --out DIR --record REL [--rescan-set REL] -- ARGS...

ARGS is the first command (without the binary; its output folder is DIR). REL is the output file,
relative to DIR, that holds the provenance to re-run. With --rescan-set, REL2 names a campaign's
set folder (chain/scan/NNN_...): the `ramtk scan` command its summary.json records is run in DIR
into a new folder, whose cloud.ply, depth.png, spheres.json and summary.json (provenance aside)
must equal the campaign's. Exit 0 when everything matches, 1 with the differences otherwise.
"""
import argparse
import csv
import io
import json
import os
import shutil
import subprocess
import sys

TEXT_SUFFIXES = {".json", ".csv", ".md", ".txt", ".yaml", ".yml"}


def drop_run_group(value, top=True):
    """The JSON value without provenance.run and without members named `seconds`."""
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if k == "seconds":
                continue
            if k == "provenance" and isinstance(v, dict):
                v = {pk: pv for pk, pv in v.items() if pk != "run"}
            out[k] = drop_run_group(v, False)
        return out
    if isinstance(value, list):
        return [drop_run_group(v, False) for v in value]
    return value


def drop_provenance(value):
    return {k: v for k, v in value.items() if k != "provenance"} if isinstance(value, dict) else value


def normalised(path, text):
    suffix = os.path.splitext(path)[1]
    if suffix == ".json":
        return json.dumps(drop_run_group(json.loads(text)), indent=1, sort_keys=True)
    if suffix == ".csv":
        rows = list(csv.reader(io.StringIO(text)))
        if rows and "seconds" in rows[0]:
            col = rows[0].index("seconds")
            rows = [r[:col] + r[col + 1:] if len(r) > col else r for r in rows]
        return "\n".join(",".join(r) for r in rows)
    if suffix == ".md":
        return "\n".join(line for line in text.split("\n") if not line.startswith("- run: "))
    return text


def files_of(folder):
    found = []
    for root, _, names in os.walk(folder):
        for n in names:
            found.append(os.path.relpath(os.path.join(root, n), folder))
    return sorted(found)


def compare_folders(first, second, problems):
    a, b = files_of(first), files_of(second)
    if a != b:
        problems.append("file lists differ: only in first %s, only in second %s" %
                        (sorted(set(a) - set(b)), sorted(set(b) - set(a))))
    for rel in sorted(set(a) & set(b)):
        pa, pb = os.path.join(first, rel), os.path.join(second, rel)
        with open(pa, "rb") as f:
            ba = f.read()
        with open(pb, "rb") as f:
            bb = f.read()
        if os.path.splitext(rel)[1] in TEXT_SUFFIXES:
            ta = ba.decode("utf-8")
            tb = bb.decode("utf-8").replace(os.path.abspath(second), os.path.abspath(first))
            tb = tb.replace(second, first)
            if normalised(rel, ta) != normalised(rel, tb):
                problems.append("%s differs (run group aside)" % rel)
        elif ba != bb:
            problems.append("%s differs (bytes)" % rel)
    return len(set(a) & set(b))


def check_comparison_sees_a_change(first, second, problems):
    """The comparison must fail once one byte of a compared file changes (outside the run group)."""
    for rel in files_of(second):
        path = os.path.join(second, rel)
        with open(path, "rb") as f:
            data = bytearray(f.read())
        digits = [i for i, c in enumerate(data) if chr(c).isdigit()]
        if os.path.splitext(rel)[1] in TEXT_SUFFIXES and os.path.splitext(rel)[1] != ".json" or not digits:
            continue
        # The last digit of a JSON file may lie in provenance.run: take the first.
        i = digits[0]
        data[i] = ord("1") if data[i] != ord("1") else ord("2")
        with open(path, "wb") as f:
            f.write(data)
        seen = []
        compare_folders(first, second, seen)
        if not seen:
            problems.append("the comparison did not see a changed byte in %s" % rel)
        return
    problems.append("no file to check the comparison with")


def with_out(command, out):
    """`command` with the value of its --out option replaced by `out`."""
    cmd = list(command)
    for i, a in enumerate(cmd):
        if a == "--out" and i + 1 < len(cmd):
            cmd[i + 1] = out
            return cmd
        if a.startswith("--out="):
            cmd[i] = "--out=" + out
            return cmd
    raise SystemExit("the recorded command has no --out: %s" % command)


def run(cmd, cwd=None):
    r = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise SystemExit("exit %d from %s\n%s%s" % (r.returncode, " ".join(cmd), r.stdout[-2000:], r.stderr[-2000:]))


def rescan_set(ramtk, out, set_folder, problems):
    """Re-scans a campaign set with the `ramtk scan` command its summary.json records."""
    with open(os.path.join(out, set_folder, "summary.json")) as f:
        recorded = json.load(f)["provenance"]["command"]
    again = os.path.abspath(out) + ".rescan"
    shutil.rmtree(again, ignore_errors=True)
    run([os.path.abspath(ramtk)] + with_out(recorded, again)[1:], cwd=out)
    for name in ["cloud.ply", "depth.png", "spheres.json", "summary.json"]:
        with open(os.path.join(out, set_folder, name), "rb") as f:
            ba = f.read()
        with open(os.path.join(again, name), "rb") as f:
            bb = f.read()
        if name.endswith(".json"):
            ja, jb = drop_run_group(drop_provenance(json.loads(ba))), drop_run_group(drop_provenance(json.loads(bb)))
            if ja != jb:
                problems.append("rescan of %s: %s differs (provenance and seconds aside)" % (set_folder, name))
        elif ba != bb:
            problems.append("rescan of %s: %s differs (bytes)" % (set_folder, name))
    print("rescanned %s with: %s" % (set_folder, " ".join(recorded)))
    shutil.rmtree(again, ignore_errors=True)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--ramtk", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--record", required=True)
    p.add_argument("--rescan-set")
    p.add_argument("args", nargs=argparse.REMAINDER)
    a = p.parse_args()
    args = a.args[1:] if a.args and a.args[0] == "--" else a.args
    again = a.out + ".again"
    for folder in (a.out, again):
        shutil.rmtree(folder, ignore_errors=True)
    run([a.ramtk] + args)
    with open(os.path.join(a.out, a.record)) as f:
        provenance = json.load(f)["provenance"]
    recorded = provenance["command"]
    if os.path.realpath(recorded[0]) != os.path.realpath(a.ramtk):
        raise SystemExit("recorded argv[0] %s is not the binary run (%s)" % (recorded[0], a.ramtk))
    run(with_out(recorded, again), cwd=provenance["run"]["working_directory"])
    problems = []
    n = compare_folders(a.out, again, problems)
    if not problems:
        check_comparison_sees_a_change(a.out, again, problems)
    if a.rescan_set:
        rescan_set(a.ramtk, a.out, a.rescan_set, problems)
    if problems:
        print("\n".join(problems))
        return 1
    print("re-ran %s: %d files equal (run group aside)" % (" ".join(recorded), n))
    shutil.rmtree(again, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

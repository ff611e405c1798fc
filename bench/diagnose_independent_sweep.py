#!/usr/bin/env python3
"""Sweep `ramtk diagnose` over data from the independent generators (issue 15).

For every kind x effect x seed: run `ramtk_indep_gen` (tests/independent, written from the physics
only), run `ramtk diagnose` on its files, compare the verdict with DIR/truth.json and print a
confusion matrix, the correct rate and the false-alarm rate.

Scoring (issue 15, "Done when"):
  * correct: the reported cause is one of truth.json's `accepted_verdicts`; an entry
    `unexplained:VAR` accepts `unexplained` only when diagnosis.json's explaining_variable names VAR;
  * `ambiguous` is correct only when the truth is in the reported look-alike set and the set has
    at most 2 members (the set is read from `ambiguous_set`, `look_alikes` or `lookalike_set`);
  * false alarm: a set whose truth is `none` reported as anything but `none`.

Usage (from the build tree's parent):
  nice -n 10 python3 bench/diagnose_independent_sweep.py --build build --seeds 1-10 \
      --kinds fringe,robot --work /tmp/indep_sweep > sweep.md
Only the standard library is used.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time

EFFECTS = {
    "fringe": ["none@1", "none@4", "none@16", "camera_defocus", "soft_knee_response",
               "projector_nonlinearity", "phase_shift_error", "defocus"],
    "robot": ["none", "joint_compliance", "joint_cyclic_error", "link_length_error",
              "thermal_length_drift", "joint_offset"],
    "laser": ["none", "beam_non_perpendicular", "speed_ripple"],
}


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        if "-" in part:
            lo, hi = part.split("-")
            seeds.extend(range(int(lo), int(hi) + 1))
        else:
            seeds.append(int(part))
    return seeds


def diagnose_command(ramtk, kind, data_dir, out_dir, robot_args):
    if kind == "fringe":
        return [ramtk, "diagnose", os.path.join(data_dir, "manifest.json"), "--out", out_dir, "--force"]
    if kind == "robot":
        return ([ramtk, "diagnose", os.path.join(data_dir, "ball.csv"), "--model", "kr150",
                 "--with", os.path.join(data_dir, "setup.json")] + robot_args + ["--out", out_dir, "--force"])
    cmd = [ramtk, "diagnose", os.path.join(data_dir, "laser_log.csv"), "--with",
           os.path.join(data_dir, "motion.json"), "--model", os.path.join(data_dir, "sensor.json"),
           "--out", out_dir, "--force"]
    return cmd


def lookalike_set(diag):
    for key in ("ambiguous_set", "look_alikes", "lookalike_set", "lookalikes"):
        if isinstance(diag.get(key), list):
            return [str(x) for x in diag[key]]
    return []


def score(truth, diag):
    """Returns (label for the confusion matrix, correct?)."""
    cause = diag.get("cause", "?")
    variable = str(diag.get("explaining_variable", ""))
    accepted = truth.get("accepted_verdicts", [truth["expected_verdict"]])
    if cause == "ambiguous":
        members = lookalike_set(diag)
        ok = len(members) <= 2 and any(a in members for a in accepted)
        return "ambiguous{" + ",".join(members) + "}", ok
    if cause == "unexplained":
        label = "unexplained(" + variable + ")" if variable else "unexplained"
        for a in accepted:
            if a == "unexplained":
                return label, True
            if a.startswith("unexplained:"):
                want = a.split(":", 1)[1]
                if re.search(r"(^|[^A-Za-z0-9])" + re.escape(want) + r"($|[^A-Za-z0-9])", variable):
                    return label, True
        return label, False
    return cause, cause in accepted


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build", help="build folder holding tools/ramtk and the generator")
    ap.add_argument("--seeds", default="1-10", help="seed list, e.g. 1-10 or 1,3,5")
    ap.add_argument("--kinds", default="fringe,robot", help="comma list of fringe, robot, laser")
    ap.add_argument("--effects", default="", help="restrict to these effects (comma list)")
    ap.add_argument("--work", default="/tmp/indep_sweep", help="scratch folder (each set is deleted after use)")
    ap.add_argument("--keep", action="store_true", help="keep the generated sets and diagnoses")
    ap.add_argument("--robot-with", default="",
                    help="extra robot --with arguments, e.g. 'thermal=none' (comma list)")
    ap.add_argument("--csv", default="", help="also write one row per run to this CSV")
    ap.add_argument("--report-from", default="",
                    help="print the report from earlier --csv files (comma list; a later file's row "
                         "replaces an earlier one of the same kind, effect and seed) and run nothing")
    args = ap.parse_args()
    if args.report_from:
        merged = {}
        for path in args.report_from.split(","):
            for r in read_rows(path):
                merged[(r["kind"], r["effect"], r["seed"])] = r
        print_report(list(merged.values()), args)
        return

    ramtk = os.path.join(args.build, "tools", "ramtk")
    gen = os.path.join(args.build, "tests", "independent", "ramtk_indep_gen")
    for exe in (ramtk, gen):
        if not os.access(exe, os.X_OK):
            sys.exit("missing executable " + exe)
    robot_args = []
    for w in filter(None, args.robot_with.split(",")):
        robot_args += ["--with", w]
    only = set(filter(None, args.effects.split(",")))
    seeds = parse_seeds(args.seeds)
    os.makedirs(args.work, exist_ok=True)

    rows = []
    failures = 0
    for kind in args.kinds.split(","):
        for effect_spec in EFFECTS[kind]:
            effect, _, gain = effect_spec.partition("@")
            if only and effect not in only and effect_spec not in only:
                continue
            for seed in seeds:
                tag = "%s_%s_%d" % (kind, effect_spec.replace("@", "_g"), seed)
                data = os.path.join(args.work, tag)
                out = os.path.join(data, "diagnosis")
                shutil.rmtree(data, ignore_errors=True)
                cmd = [gen, "--kind", kind, "--effect", effect, "--seed", str(seed), "--out", data]
                if gain:
                    cmd += ["--gain", gain]
                g = subprocess.run(cmd, capture_output=True, text=True)
                if g.returncode != 0:
                    print("generator failed: %s\n%s" % (" ".join(cmd), g.stderr), file=sys.stderr)
                    failures += 1
                    continue
                with open(os.path.join(data, "truth.json")) as f:
                    truth = json.load(f)
                t0 = time.time()
                d = subprocess.run(diagnose_command(ramtk, kind, data, out, robot_args),
                                   capture_output=True, text=True)
                seconds = time.time() - t0
                diag = {}
                path = os.path.join(out, "diagnosis.json")
                if d.returncode == 0 and os.path.exists(path):
                    with open(path) as f:
                        diag = json.load(f)
                else:
                    diag = {"cause": "error"}
                    failures += 1
                    print("diagnose failed on %s: %s" % (tag, d.stderr.strip()[-400:]), file=sys.stderr)
                label, ok = score(truth, diag)
                heldout = diag.get("heldout") or {}
                excess = heldout.get("excess_removed")
                row = {"kind": kind, "effect": effect_spec, "seed": seed, "truth": truth["expected_verdict"],
                       "reported": label, "correct": ok, "confidence": diag.get("confidence"),
                       "excess_removed": excess, "rms_before": heldout.get("rms_before"),
                       "noise_floor": diag.get("noise_floor_rms"), "seconds": round(seconds, 1),
                       "unexplained_accepted": any(a.startswith("unexplained")
                                                   for a in truth.get("accepted_verdicts", []))}
                rows.append(row)
                print("%-40s truth %-24s -> %-40s %s (%.1f s)" % (tag, row["truth"], label,
                      "ok" if ok else "MISS", seconds), file=sys.stderr, flush=True)
                if not args.keep:
                    shutil.rmtree(data, ignore_errors=True)

    if args.csv:
        with open(args.csv, "w") as f:
            keys = list(rows[0].keys()) if rows else []
            f.write(",".join(keys) + "\n")
            for r in rows:
                f.write(",".join(str(r[k]) for k in keys) + "\n")
    print_report(rows, args)
    if failures:
        sys.exit("%d runs failed (generator or diagnose error)" % failures)


def read_rows(path):
    def value(text):
        if text in ("True", "False"):
            return text == "True"
        if text == "None":
            return None
        try:
            return float(text) if any(c in text for c in ".e") else int(text)
        except ValueError:
            return text
    rows = []
    with open(path) as f:
        lines = f.read().splitlines()
    keys = lines[0].split(",")
    for line in lines[1:]:
        # `reported` may hold commas (an ambiguous set in braces): rebuild it from the middle fields.
        fields = line.split(",")
        extra = len(fields) - len(keys)
        i = keys.index("reported")
        fields[i:i + extra + 1] = [",".join(fields[i:i + extra + 1])]
        row = {k: value(v) for k, v in zip(keys, fields)}
        row["reported"] = str(fields[i])
        row["truth"] = str(row["truth"])
        row["effect"] = str(row["effect"])
        rows.append(row)
    return rows


def print_report(rows, args):
    print("# Independent-generator sweep of `ramtk diagnose`\n")
    if args.report_from:
        print("merged from %s\n" % args.report_from)
    else:
        print("seeds %s, kinds %s%s\n" % (args.seeds, args.kinds,
              (", robot --with " + args.robot_with) if args.robot_with else ""))
    for kind in sorted({r["kind"] for r in rows}):
        kr = [r for r in rows if r["kind"] == kind]
        labels = []
        for r in kr:
            if r["reported"] not in labels:
                labels.append(r["reported"])
        effects = []
        for r in kr:
            if r["effect"] not in effects:
                effects.append(r["effect"])
        print("## %s\n" % kind)
        print("| truth \\ reported | " + " | ".join(labels) + " | correct | median RMS before / noise floor |")
        print("|---|" + "---|" * (len(labels) + 2))
        for e in effects:
            er = [r for r in kr if r["effect"] == e]
            cells = [str(sum(1 for r in er if r["reported"] == l) or "") for l in labels]
            ratios = sorted(r["rms_before"] / r["noise_floor"] for r in er
                            if r.get("rms_before") is not None and r.get("noise_floor"))
            ratio = "%.2f" % ratios[len(ratios) // 2] if ratios else "-"
            print("| %s | %s | %d/%d | %s |" % (e, " | ".join(cells), sum(r["correct"] for r in er), len(er), ratio))
        summarize(kr, "%s" % kind)
        print()
    summarize(rows, "all kinds")


def summarize(rows, name):
    n = len(rows)
    if n == 0:
        return
    correct = sum(r["correct"] for r in rows)
    clean = [r for r in rows if r["truth"] == "none"]
    alarms = sum(1 for r in clean if r["reported"] != "none")
    named = [r for r in rows if r["truth"] != "none" and r["correct"] and r["excess_removed"] is not None
             and r["reported"] not in ("none",) and not r["reported"].startswith("unexplained")]
    gain = sorted(r["excess_removed"] for r in named)
    med = gain[len(gain) // 2] if gain else float("nan")
    half = sum(1 for g in gain if g >= 0.5)
    lenient = sum(1 for r in rows if not r["correct"] and r["reported"].startswith("unexplained")
                  and r.get("unexplained_accepted"))
    if lenient:
        print("\n%s: %d more sets would be correct if `unexplained` counted with any explaining variable"
              % (name, lenient))
    print("\n%s: correct %d/%d = %.1f %%; false alarms %d/%d = %.1f %%; median excess removed where a "
          "cause is named correctly %.2f (%d sets, %d of them >= 50 %%)" % (name, correct, n, 100.0 * correct / n,
          alarms, len(clean), 100.0 * alarms / max(1, len(clean)), med, len(gain), half))


if __name__ == "__main__":
    main()

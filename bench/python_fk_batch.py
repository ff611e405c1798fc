#!/usr/bin/env python3
"""Batch forward kinematics from Python against the C++ loop (docs/python.md).

Times ramtk.fk(model, q) on an N×6 array of random KR150 joint sets (the argument checks, one C++
loop without the GIL, the N×4×4 result) and compares the time per joint set with BM_Fk_Ramtk of
kinematics_bench (BaseFromFlange in a C++ loop, same robot). Prints the ratio; asserts nothing
about time (a shared machine).

    PYTHONPATH=build/python python3 bench/python_fk_batch.py --bench build/bench/kinematics_bench
"""
import argparse
import json
import subprocess
import time

import numpy as np

import ramtk

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--bench", default="build/bench/kinematics_bench", help="the kinematics_bench binary")
parser.add_argument("--rows", type=int, default=100_000, help="joint sets per call")
parser.add_argument("--repeat", type=int, default=7, help="timed calls (the fastest is reported)")
args = parser.parse_args()

robot = ramtk.RobotModel.read(ramtk.robot_path("kuka_kr150_r3100"))
q = np.random.default_rng(1).uniform(-120, 120, size=(args.rows, 6))
ramtk.fk(robot, q[:10])
times = []
for _ in range(args.repeat):
    t0 = time.perf_counter()
    t = ramtk.fk(robot, q)
    times.append(time.perf_counter() - t0)
assert t.shape == (args.rows, 4, 4)
python_ns = min(times) / args.rows * 1e9

out = subprocess.run([args.bench, "--benchmark_filter=^BM_Fk_Ramtk$", "--benchmark_repetitions=5",
                      "--benchmark_format=json"], check=True, capture_output=True, text=True).stdout
runs = [b for b in json.loads(out)["benchmarks"] if b.get("run_type") == "iteration"]
cpp_ns = min(b["real_time"] for b in runs)  # ns per BaseFromFlange
print(f"ramtk.fk, {args.rows} joint sets: {min(times) * 1e3:.2f} ms, {python_ns:.1f} ns per set "
      f"(median of {args.repeat}: {np.median(times) * 1e3:.2f} ms)")
print(f"C++ loop (BM_Fk_Ramtk): {cpp_ns:.1f} ns per set")
print(f"ratio python/C++: {python_ns / cpp_ns:.2f}")

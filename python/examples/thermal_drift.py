#!/usr/bin/env python3
"""Worked example of docs/python.md: simulate a warming robot (the thesis's thermal experiment),
identify the drift of its parameters per cycle from the ball measurements held in numpy, and
compare with the simulator's truth; the result goes to JSON through to_dict().

    python3 thermal_drift.py [--out DIR]      # from any folder, with ramtk installed

Run by ctest from / in a fresh virtual environment (python.wheel_venv) and by pytest.
"""
import argparse
import json
import pathlib
import tempfile
from typing import Dict

import numpy as np
import numpy.typing as npt

import ramtk


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--out", default="", help="scratch folder (default: a temporary one)")
    args = parser.parse_args()
    out = pathlib.Path(args.out or tempfile.mkdtemp(prefix="ramtk_example_"))
    out.mkdir(parents=True, exist_ok=True)

    robot = ramtk.RobotModel.read(ramtk.robot_path("kuka_kr150_r3100"))
    sim = ramtk.simulate_thermal(robot, out / "thermal", seed=3, cycles=12, force=True)
    print(f"drifting parameters: {', '.join(sim.drifting_params)}")

    # The ball measurements as numpy columns (e.g. assembled from your own logging).
    with open(sim.ball, encoding="utf-8") as f:
        names = f.readline().strip().split(",")
    values = np.loadtxt(sim.ball, delimiter=",", skiprows=1, ndmin=2)
    columns: Dict[str, npt.NDArray[np.float64]] = {name: values[:, i] for i, name in enumerate(names)}
    drift = ramtk.thermal_identify(robot, sim.setup, columns, sim.drifting_params)
    print(drift.report)

    # Against the truth (30 x cycles; lengths in mm, angles in rad): the first cycle is the
    # reference, so both are compared as changes from it.
    truth = sim.true_delta_x[[ramtk.PARAM_NAMES.index(p) for p in drift.params]]
    for i, p in enumerate(drift.params):
        got = drift.delta_x[i] - drift.delta_x[i, 0]
        want = truth[i, : got.size] - truth[i, 0]
        scale = 1.0 if p.startswith(("d", "a")) and not p.startswith("alpha") else 180 / np.pi * 3600
        unit = "mm" if scale == 1.0 else "arcsec"
        print(f"{p:7s} last cycle {got[-1] * scale:+9.4f} {unit} (truth {want[-1] * scale:+9.4f})")

    report = out / "drift.json"
    report.write_text(json.dumps(drift.to_dict(), indent=1))
    print(f"wrote {report}")
    assert drift.rank == len(drift.params)
    print("ok")


if __name__ == "__main__":
    main()

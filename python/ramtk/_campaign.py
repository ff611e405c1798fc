"""The campaign layer: batch scans with shards and merge, measure (centres + controller log ->
measurement table), the campaign digital twin, the robot calibration and hand-eye. Options are
named as the commands' options; mm and degrees."""
from __future__ import annotations

import os
from typing import Any, Dict, Optional, Union

import numpy as np
import numpy.typing as npt

from . import _checks as check
from . import _core
from ._results import BatchResult, CampaignResult, HandEye, Measurements, RobotCalibration, as_type
from ._robot import robot_model
from ._vision import ProgressFn, scan_options

PathLike = Union[str, "os.PathLike[str]"]


def scan_batch(batch: PathLike, out: PathLike, *, shard: Optional[str] = None, jobs: int = 2, force: bool = False,
               resume: bool = False, progress: Optional[ProgressFn] = None, **options: Any) -> BatchResult:
    """`ramtk scan --batch LIST [--shard K/N]`: scans every listed set (or shard K of N: every N-th
    set from the K-th) into out/<set folder>, and writes out/results.csv (a shard:
    results.shard-K-of-N.csv; join them with ramtk.merge). `options` are ramtk.scan's keyword
    options (radius, roi, ...). An earlier run's results are kept unless force or resume."""
    opts = scan_options(**options)
    if shard is not None and not isinstance(shard, str):
        raise check.fail("shard", "expected 'K/N'")
    d = _core.scan_batch(check.path(batch, "batch"), check.path(out, "out"), opts, check.count(jobs, "jobs", 1),
                         shard or "", check.flag(force, "force"), check.flag(resume, "resume"), progress)
    return as_type(BatchResult, d)


def merge(batch: PathLike, out: PathLike, *, force: bool = False, allow_errors: bool = False) -> str:
    """`ramtk merge`: joins the shards' results in `out` into out/results.csv; returns its path."""
    return _core.merge(check.path(batch, "batch"), check.path(out, "out"), check.flag(force, "force"),
                       check.flag(allow_errors, "allow_errors"))


def _columns(text: str) -> Dict[str, npt.NDArray[np.float64]]:
    lines = text.splitlines()
    names = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:] if line]
    out: Dict[str, npt.NDArray[np.float64]] = {}
    for i, name in enumerate(names):
        try:
            out[name] = np.array([float(r[i]) for r in rows])
        except ValueError:
            continue  # a text column (an operator's note) is left out of the numeric columns
    return out


def measure(scans: PathLike, log: PathLike, *, out: Optional[PathLike] = None, time_tolerance: float = 0.5,
            by_time: bool = False) -> Measurements:
    """`ramtk measure`: joins the centres of a scan batch (its results.csv) with the controller log
    (by the log's `set` column, or by time within time_tolerance s) into the robot-measurement
    table; writes it to `out` when given."""
    d = _core.measure(check.path(scans, "scans"), check.path(log, "log"), "" if out is None else check.path(out, "out"),
                      check.number(time_tolerance, "time_tolerance", 0.0, True), check.flag(by_time, "by_time"))
    d["columns"] = _columns(d["table"])
    return as_type(Measurements, d)


def simulate_campaign(robot: PathLike, out: PathLike, *, cycles: int = 4, poses: int = 8, points: int = 8,
                      period: float = 1800.0, scale: float = 0.25, supersampling: int = 2,
                      repeatability: float = 0.015, seed: int = 1, jobs: int = 2, screen_keep: int = 8,
                      report: bool = False, force: bool = False,
                      progress: Optional[ProgressFn] = None) -> CampaignResult:
    """`ramtk simulate campaign`: renders the ball's fringe sets for cycles × poses of a warming
    robot, then runs scan → measure → sensor-to-robot calibration → drift identification →
    compensation, and returns the error budget against truth (also budget.json / budget.md in out).
    period: s between cycles; scale: camera window scale; repeatability: robot σ per axis (mm)."""
    # The limits of CampaignOptions::Validate, checked here to name the argument.
    opts = {"cycles": check.count(cycles, "cycles", 2), "poses": check.count(poses, "poses", 5),
            "points": check.count(points, "points", 1), "period": check.number(period, "period", 0.0, True),
            "scale": check.number(scale, "scale", 0.0, True),
            "supersampling": check.count(supersampling, "supersampling", 1),
            "screen_keep_max": check.count(30 - screen_keep, "screen_keep", 0),
            "repeatability": check.number(repeatability, "repeatability", 0.0), "seed": check.count(seed, "seed", 0),
            "jobs": check.count(jobs, "jobs", 1), "screen_keep": check.count(screen_keep, "screen_keep", -1),
            "report": check.flag(report, "report")}
    if opts["scale"] <= 0.05 or opts["scale"] > 1.0:
        raise check.fail("scale", f"must be in (0.05, 1], got {scale}")
    if opts["supersampling"] > 8:
        raise check.fail("supersampling", f"must be in 1..8, got {supersampling}")
    d = _core.simulate_campaign(robot_model(robot), check.path(out, "out"), opts, check.flag(force, "force"), progress)
    return as_type(CampaignResult, d)


def calibrate_robot(robot: PathLike, data: PathLike, *, format: Optional[PathLike] = None,
                    out: Optional[PathLike] = None, force: bool = False, remove_drift: bool = False,
                    setup_only: bool = False, no_rotation: bool = False, no_cyclic: bool = False,
                    no_compliance: bool = False, split: str = "random", loss: str = "none",
                    covariance: str = "scaled", folds: int = 5, seed: int = 1,
                    progress: Optional[ProgressFn] = None) -> RobotCalibration:
    """`ramtk calib robot`: kinematic calibration from tracker points or 6-D poses (docs/
    robot_calibration.md). format: the tracker file's column YAML; out: a folder for robot.yaml,
    calibration.json and residuals.csv; split 'random' or 'blocks'; loss 'none', 'huber' or
    'cauchy'; covariance 'scaled', 'sandwich' or 'nominal'."""
    for name, value, allowed in (("split", split, ("random", "blocks")), ("loss", loss, ("none", "huber", "cauchy")),
                                 ("covariance", covariance, ("scaled", "sandwich", "nominal"))):
        if value not in allowed:
            raise check.fail(name, f"expected one of {', '.join(allowed)}, got {value!r}")
    opts = {"setup_only": check.flag(setup_only, "setup_only"), "no_rotation": check.flag(no_rotation, "no_rotation"),
            "no_cyclic": check.flag(no_cyclic, "no_cyclic"), "no_compliance": check.flag(no_compliance, "no_compliance"),
            "split": split, "loss": loss, "covariance": covariance, "folds": check.count(folds, "folds", 2),
            "seed": check.count(seed, "seed", 0)}
    d = _core.calibrate_robot(check.path(robot, "robot"), check.path(data, "data"),
                              "" if format is None else check.path(format, "format"),
                              "" if out is None else check.path(out, "out"), check.flag(force, "force"),
                              check.flag(remove_drift, "remove_drift"), opts, progress)
    return as_type(RobotCalibration, d)


def hand_eye(base_from_flange: npt.ArrayLike, camera_from_board: npt.ArrayLike, *, method: str = "shah",
             refine: bool = True) -> HandEye:
    """Hand-eye of a camera on a stand seeing a board on the flange (`ramtk calib hand-eye`):
    N flange poses from the controller and N board poses measured by the camera (N×4×4, mm; rigid).
    method 'shah' or 'li' (OpenCV's closed form), refined by least squares unless refine=False."""
    flanges = check.float_array(base_from_flange, "base_from_flange")
    boards = check.float_array(camera_from_board, "camera_from_board")
    for name, a in (("base_from_flange", flanges), ("camera_from_board", boards)):
        if a.ndim != 3 or a.shape[1:] != (4, 4):
            raise check.fail(name, f"expected N×4×4 poses, got shape {a.shape}")
        for i in range(a.shape[0]):
            check.pose(a[i], f"{name}[{i}]")
    if flanges.shape != boards.shape:
        raise check.fail("camera_from_board", f"{boards.shape[0]} poses beside {flanges.shape[0]} flange poses")
    if method not in ("shah", "li"):
        raise check.fail("method", f"expected 'shah' or 'li', got {method!r}")
    d = _core.hand_eye(np.ascontiguousarray(flanges), np.ascontiguousarray(boards), method,
                       check.flag(refine, "refine"))
    return as_type(HandEye, d)



"""Robot models: forward kinematics and the 30-parameter point Jacobian for one joint set or a
batch (N×6), inverse kinematics, and the sensor-to-robot calibration from a measurement table.
Joint angles in degrees (controller values), lengths in mm, poses as 4×4 arrays."""
from __future__ import annotations

import os
from typing import Union

import numpy as np
import numpy.typing as npt

from . import _checks as check
from . import _core
from ._results import IkSolution, SensorRobotCalibration, as_type
from ._tables import Table, table_source

PathLike = Union[str, "os.PathLike[str]"]
RobotLike = Union[_core.RobotModel, PathLike]
F64 = npt.NDArray[np.float64]

_D = _core.defaults()


def robot_model(robot: RobotLike, field: str = "robot") -> _core.RobotModel:
    """A RobotModel, or the robot YAML at a path read into one."""
    if isinstance(robot, _core.RobotModel):
        return robot
    return _core.RobotModel.read(check.path(robot, field))


def fk(model: RobotLike, q_deg: npt.ArrayLike) -> F64:
    """base_from_flange (mm) at controller joints q_deg (degrees): 4×4 for 6 angles, N×4×4 for an
    N×6 batch (computed in one C++ loop)."""
    q, single = check.joints(q_deg, "q_deg")
    t = _core.fk_batch(robot_model(model, "model"), q)
    out: F64 = t[0] if single else t
    return out


def point_jacobian(model: RobotLike, q_deg: npt.ArrayLike, point_in_flange_mm: npt.ArrayLike = (0.0, 0.0, 0.0)) -> F64:
    """Derivative of the point (given in the flange frame, mm) in the base frame w.r.t. the 30
    parameters in ramtk.PARAM_NAMES order (mm per mm, mm per rad; thesis eq. 3-6): 3×30 for 6
    angles (degrees), N×3×30 for an N×6 batch."""
    q, single = check.joints(q_deg, "q_deg")
    p = check.vector(point_in_flange_mm, "point_in_flange_mm", 3)
    j = _core.point_jacobian_batch(robot_model(model, "model"), q, p)
    out: F64 = j[0] if single else j
    return out


def ik(model: RobotLike, pose: npt.ArrayLike, seed_deg: npt.ArrayLike) -> IkSolution:
    """Controller joints (degrees) reaching the 4×4 base_from_flange pose (mm; a rigid transform),
    from a seed joint set (degrees)."""
    target = check.pose(pose, "pose")
    seed, single = check.joints(seed_deg, "seed_deg")
    if not single:
        raise check.fail("seed_deg", "expected one joint set of 6 angles")
    d = _core.ik(robot_model(model, "model"), target, seed)
    d["q_deg"] = np.asarray(d["q_deg"])
    return as_type(IkSolution, d)


def calibrate_sensor_robot(robot: RobotLike, measurements: Table, *, use_covariance: bool = _D["use_covariance"],
                           robot_noise_mm: float = _D["robot_noise_mm"]) -> SensorRobotCalibration:
    """sensor_from_base (4×4, mm) and ball_in_flange (mm) with covariance, from a ball measurement
    table: a CSV file (`ramtk measure`), a dict of columns or a 2-D array (ramtk.measurement_table).
    use_covariance weights each centre by its cov_xx..cov_yz columns when present; robot_noise_mm
    adds the robot's positioning noise (mm, 1σ per axis) to each centre's covariance."""
    source, text = table_source(measurements, "measurements")
    d = _core.calibrate_sensor_robot(robot_model(robot), source, text, check.flag(use_covariance, "use_covariance"),
                                     check.number(robot_noise_mm, "robot_noise_mm", 0.0))
    return as_type(SensorRobotCalibration, d)



"""Typed results: frozen dataclasses with a short readable repr and to_dict() for JSON (numpy
arrays become lists). Large arrays (clouds, images) are views of the C++ buffers, not copies."""
from __future__ import annotations

import dataclasses
import os
from typing import Any, Dict, List, Optional, Type, TypeVar

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
F32 = npt.NDArray[np.float32]


def _jsonable(v: Any) -> Any:
    if isinstance(v, _Result):
        return v.to_dict()
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    return v


def _short(v: Any) -> str:
    if isinstance(v, np.ndarray):
        if v.size <= 6:
            return np.array2string(v, precision=4, separator=", ")
        return f"<{v.dtype} array {'×'.join(map(str, v.shape))}>"
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, str):
        return repr(v if len(v) <= 70 else v[:67] + "...")
    if isinstance(v, dict):
        return f"{{{len(v)} keys}}"
    if isinstance(v, list) and len(v) > 3:
        return f"[{len(v)} items]"
    if isinstance(v, list):
        return "[" + ", ".join(_short(x) for x in v) + "]"
    return repr(v)


class _Result:
    """Base of the result classes: repr shows scalars and array shapes; to_dict() is JSON-ready."""

    def to_dict(self) -> Dict[str, Any]:
        return {f.name: _jsonable(getattr(self, f.name))
                for f in dataclasses.fields(self)
                if not f.name.startswith("_")}

    def __repr__(self) -> str:
        parts = [f"{f.name}={_short(getattr(self, f.name))}"
                 for f in dataclasses.fields(self)
                 if not f.name.startswith("_")]
        return f"ramtk.{type(self).__name__}({', '.join(parts)})"


@dataclasses.dataclass(frozen=True, repr=False)
class Sphere(_Result):
    """A fitted sphere in the cloud's frame (mm): centre, radius and the centre's covariance."""
    centre_mm: F64
    radius_mm: float
    radius_sigma_mm: float
    centre_covariance_mm2: F64
    rms_mm: float
    num_points: int
    num_outliers: int
    variance_factor: float
    correlation_factor: float  # neighbour-correlation inflation already in the covariance (1 = independent)
    crlb_centre_sigma_mm: F64  # Cramér–Rao bound of the centre along x, y, z (mm), correlation included
    crlb_radius_sigma_mm: float  # Cramér–Rao bound of the radius (mm; 0 when held fixed)

    @property
    def centre_sigma_mm(self) -> F64:
        """σ of the centre along x, y, z (mm)."""
        return np.sqrt(np.diag(self.centre_covariance_mm2))


@dataclasses.dataclass(frozen=True, repr=False)
class TruthSphere(_Result):
    """A simulator's true sphere (truth/truth.json), left-camera frame, mm."""
    name: str
    centre_mm: F64
    radius_mm: float


@dataclasses.dataclass(frozen=True, repr=False)
class Cloud(_Result):
    """A triangulated cloud in the left-camera frame: views of the C++ buffers (no copy)."""
    points_mm: F32  # N×3 x, y, z (mm)
    sigma_mm: F32  # N: σ along the left camera's ray (mm)
    quality: F32  # N: decoder modulation over its noise

    def __len__(self) -> int:
        return int(self.points_mm.shape[0])


@dataclasses.dataclass(frozen=True, repr=False)
class ScanResult(_Result):
    """`ramtk scan`: the cloud, the depth map (z mm per left pixel, NaN none), the spheres."""
    cloud: Cloud
    depth_mm: F32
    spheres: List[Sphere]
    termination: str  # "success", "no result" or "cancelled"
    report: str
    summary: Dict[str, Any]
    _data: Any = dataclasses.field(default=None, compare=False)

    def write(self, out_dir: "str | os.PathLike[str]", *, set_label: Optional[str] = None, force: bool = False,
              html_report: bool = False) -> None:
        """Writes cloud.ply, spheres.json, depth.png and summary.json into out_dir as `ramtk scan
        --out` does (set_label: the set named in cloud.ply's comment; default the scanned manifest)."""
        label = self.summary.get("set", "") if set_label is None else set_label
        self._data.write(os.fspath(out_dir), label, force, html_report)


@dataclasses.dataclass(frozen=True, repr=False)
class Decoded(_Result):
    """One decoded camera: images as views of the C++ buffers (no copy)."""
    coordinate: F32  # projector px, NaN invalid
    wrapped: F32  # rad
    background: F32  # DN
    modulation: F32  # DN
    mask: npt.NDArray[np.uint8]  # 255 valid
    sigma_phase: F32  # rad
    sigma_coordinate: F32  # projector px
    summary: Dict[str, Any]


@dataclasses.dataclass(frozen=True, repr=False)
class FringeSet(_Result):
    """A rendered fringe set (`ramtk simulate fringe`): its files."""
    out_dir: str
    frames: int  # images per camera
    width: int  # px
    height: int  # px
    manifest: str
    truth: str


@dataclasses.dataclass(frozen=True, repr=False)
class IkSolution(_Result):
    """Inverse kinematics: controller joints (deg) and the remaining error."""
    q_deg: F64
    converged: bool
    iterations: int
    final_position_error_mm: float
    final_rotation_error_deg: float
    report: str


@dataclasses.dataclass(frozen=True, repr=False)
class SensorRobotCalibration(_Result):
    """sensor_from_base (4×4, mm) and ball_in_flange (mm) with their covariance."""
    sensor_from_base: F64
    ball_in_flange_mm: F64
    covariance: F64  # 9×9 over [φ rad, t mm, ball mm]
    has_covariance: bool
    rms_mm: float
    rotation_std_arcsec: F64
    translation_std_mm: F64
    ball_std_mm: F64
    converged: bool
    report: str


@dataclasses.dataclass(frozen=True, repr=False)
class ThermalSimulation(_Result):
    """The thesis thermal experiment simulated: truth and the files written."""
    drifting_params: List[str]
    true_delta_x: F64  # 30 × cycles (mm, rad), ramtk.PARAM_NAMES order
    ball: str
    monitoring: str
    setup: str


@dataclasses.dataclass(frozen=True, repr=False)
class DriftEstimate(_Result):
    """ΔX of the named parameters per cycle (thesis eq. 3-8)."""
    params: List[str]
    cycles: List[int]
    delta_x: F64  # params × cycles; mm for lengths, rad for angles
    sigma: F64  # standard deviation of delta_x, same shape and units (NaN: parameter not kept)
    rank: int
    condition_number: float
    rms_residual_mm: float
    report: str


@dataclasses.dataclass(frozen=True, repr=False)
class Screening(_Result):
    """Parameter screening (thesis §3.2): the kept parameters and the elimination steps."""
    selected: List[str]
    final_lambda_percent: float
    steps: List[Dict[str, Any]]
    table: str


@dataclasses.dataclass(frozen=True, repr=False)
class Diagnosis(_Result):
    """`ramtk diagnose`: diagnosis.json as a dict, its one-line verdict and the report paths."""
    one_line: str
    data: Dict[str, Any]
    report_md: Optional[str]
    diagnosis_json: Optional[str]


T = TypeVar("T", bound=_Result)


def as_type(cls: Type[T], d: Dict[str, Any]) -> T:
    """The dataclass `cls` from the C++ layer's dict (keys = field names)."""
    names = {f.name for f in dataclasses.fields(cls)}
    return cls(**{k: v for k, v in d.items() if k in names})



@dataclasses.dataclass(frozen=True, repr=False)
class BatchResult(_Result):
    """`ramtk scan --batch`: counts per status and the results table (results.csv's text)."""
    results: str  # the results file written ("" when cancelled)
    sets: int
    ok: int
    no_sphere: int
    errors: int
    cancelled: int
    report: str
    csv: str


@dataclasses.dataclass(frozen=True, repr=False)
class Measurements(_Result):
    """`ramtk measure`: the robot-measurement table (ball centres in the sensor frame, mm, with
    their covariance) as columns, ready for calibrate_sensor_robot / thermal_identify."""
    columns: Dict[str, F64]
    written: int
    match: str  # "id" or "time"
    left_out: List[Dict[str, Any]]
    warnings: List[str]
    report: str
    table: str  # the CSV text


@dataclasses.dataclass(frozen=True, repr=False)
class CampaignResult(_Result):
    """`ramtk simulate campaign`: the error budget stage by stage against truth (budget.json)."""
    out_dir: str
    cancelled: bool
    budget: Dict[str, Any]
    budget_md: str
    left_out: List[str]
    report: str


@dataclasses.dataclass(frozen=True, repr=False)
class RobotCalibration(_Result):
    """`ramtk calib robot`: the calibrated robot file, the unknowns with σ (calibration.json) and
    the RMS per coordinate before, after and held out (mm)."""
    termination: str
    rms_before_mm: float
    rms_after_mm: float
    rms_held_out_mm: float
    robot_yaml: str
    calibration: Dict[str, Any]
    table: str
    warnings: List[str]
    report: str


@dataclasses.dataclass(frozen=True, repr=False)
class HandEye(_Result):
    """Hand-eye of a camera on a stand: camera_from_base and flange_from_board (4×4, mm)."""
    camera_from_base: F64
    flange_from_board: F64
    rotation_residual_deg: List[float]
    translation_residual_mm: List[float]
    rms_rotation_deg: float
    rms_translation_mm: float
    report: str

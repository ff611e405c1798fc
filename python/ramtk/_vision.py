"""Fringe decoding, the scan pipeline, sphere fitting and the fringe simulator, from files or from
numpy arrays in memory. Lengths in mm, all 3-D results in the left-camera frame."""
from __future__ import annotations

import json
import os
import tempfile
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from . import _checks as check
from . import _core
from ._results import Cloud, Decoded, FringeSet, ScanResult, Sphere, TruthSphere, as_type

PathLike = Union[str, "os.PathLike[str]"]
Frames = Sequence[npt.NDArray[Any]]
# A pattern sequence: a manifest file, or its contents as a dict (ramtk.read_manifest).
SequenceLike = Union[PathLike, Mapping[str, Any]]
# progress(stage, done, total): return False to cancel; Ctrl-C also cancels (KeyboardInterrupt).
ProgressFn = Callable[[str, int, int], Optional[bool]]

_D: Dict[str, Any] = _core.defaults()


def read_image(path: PathLike) -> npt.NDArray[Any]:
    """A single-channel image as stored (uint8, uint16 or float32 array)."""
    return _core.read_image(check.path(path, "path"))


def read_manifest(path: PathLike) -> Dict[str, Any]:
    """A fringe-set manifest as a dict (validated), plus 'resolved_images': each camera's image paths."""
    return _core.read_manifest(check.path(path, "path"))


def read_truth_spheres(path: PathLike) -> List[TruthSphere]:
    """The true spheres of a simulated set (truth/truth.json): centre in the left-camera frame, mm."""
    return [TruthSphere(**d) for d in _core.read_truth_spheres(check.path(path, "path"))]


def _sequence(sequence: Optional[SequenceLike], field: str = "sequence") -> "tuple[str, str]":
    """(manifest JSON text, the path that names it in errors and anchors relative paths)."""
    if sequence is None:
        raise check.fail(field, "frames in memory need the pattern sequence: a manifest path or dict")
    if isinstance(sequence, Mapping):
        d = {k: v for k, v in sequence.items() if k != "resolved_images"}
        return json.dumps(d), f"<{field}>"
    p = check.path(sequence, field)
    try:
        with open(p, encoding="utf-8") as f:
            return f.read(), p
    except OSError as e:
        raise check.fail(field, f"cannot read {p}: {e.strerror}") from None


def _decode_options(min_modulation: float, sigma_intensity: float, no_nonlinearity: bool, phase_filter: int,
                    whole_residual_sigma: bool) -> Dict[str, Any]:
    return {"min_modulation": check.number(min_modulation, "min_modulation", 0.0),
            "sigma_intensity": check.number(sigma_intensity, "sigma_intensity", 0.0),
            "no_nonlinearity": check.flag(no_nonlinearity, "no_nonlinearity"),
            "phase_filter": check.count(phase_filter, "phase_filter", 0),
            "whole_residual_sigma": check.flag(whole_residual_sigma, "whole_residual_sigma")}


def decode(frames: Union[PathLike, Frames], camera: str = "left", sequence: Optional[SequenceLike] = None, *,
           full_scale: Optional[float] = None, min_modulation: float = _D["min_modulation"],
           sigma_intensity: float = 0.0, no_nonlinearity: bool = False, phase_filter: int = 0,
           whole_residual_sigma: bool = False) -> Decoded:
    """Decodes one camera of a fringe set (`ramtk decode`).

    frames: a manifest path (the camera's images are read), or the camera's frames in memory
        (2-D uint8 / uint16 / float32 arrays in the sequence's order; then `sequence` is needed).
    sequence: the pattern sequence of in-memory frames: a manifest path or dict.
    full_scale: DN of a saturated pixel; default 255 (uint8) or 65535 (uint16).
    min_modulation: pixels whose modulation is below this fraction of full scale are invalid.
    sigma_intensity: intensity noise (DN); 0 estimates it from the fit.
    phase_filter: smoothing window half-width (px, 0 = off, at most 6).
    Returns coordinate (projector px, NaN invalid), wrapped (rad), background and modulation (DN),
    mask (255 valid), sigma_phase (rad), sigma_coordinate (projector px), summary.
    """
    opts = _decode_options(min_modulation, sigma_intensity, no_nonlinearity, phase_filter, whole_residual_sigma)
    if isinstance(frames, (str, os.PathLike)):
        return as_type(Decoded, _core.decode(os.fspath(frames), camera, opts))
    fs = check.frames(frames, "frames")
    text, where = _sequence(sequence)
    return as_type(Decoded, _core.decode_frames(fs, text, where, check.full_scale(full_scale, fs[0]), camera, opts))


def _calibration_path(calibration: Union[None, PathLike, _core.StereoCalibration], keep: List[Any]) -> str:
    if calibration is None:
        return ""
    if isinstance(calibration, _core.StereoCalibration):
        tmp = tempfile.TemporaryDirectory(prefix="ramtk_calibration_")
        keep.append(tmp)
        p = os.path.join(tmp.name, "calibration.yaml")
        calibration.write(p)
        return p
    return check.path(calibration, "calibration")


def scan_options(*, calibration: Optional[PathLike] = None, radius: float = 19.05, fix_radius: bool = False,
                 spheres: int = 1, min_depth: float = 100.0, max_depth: float = 10000.0, phase_filter: int = 0,
                 roi: str = "full", roi_margin: float = _D["roi_margin"], roi_stride: int = 0,
                 no_nonlinearity: bool = False, whole_residual_sigma: bool = False,
                 lr_sigma_factor: float = _D["lr_sigma_factor"], load_whole_frames: bool = False,
                 noise_term: bool = True, kernel_estimate: str = "off") -> Dict[str, Any]:
    """The scan's options checked, as the dict the C++ layer reads (ramtk.scan documents them)."""
    if not isinstance(roi, str):
        raise check.fail("roi", f"expected 'full', 'auto' or 'X,Y,Z', got {type(roi).__name__}")
    if kernel_estimate not in ("auto", "off"):
        raise check.fail("kernel_estimate", f"expected 'auto' or 'off', got {kernel_estimate!r}")
    opts: Dict[str, Any] = {
        "calibration": "" if calibration is None else check.path(calibration, "calibration"),
        "radius": check.number(radius, "radius", 0.0), "fix_radius": check.flag(fix_radius, "fix_radius"),
        "spheres": check.count(spheres, "spheres", 1), "min_depth": check.number(min_depth, "min_depth", 0.0, True),
        "max_depth": check.number(max_depth, "max_depth", 0.0, True), "roi": roi,
        "roi_margin": check.number(roi_margin, "roi_margin", 0.0), "roi_stride": check.count(roi_stride, "roi_stride", 0),
        "lr_sigma_factor": check.number(lr_sigma_factor, "lr_sigma_factor", 0.0),
        "load_whole_frames": check.flag(load_whole_frames, "load_whole_frames"),
        "noise_term": check.flag(noise_term, "noise_term"), "kernel_estimate": kernel_estimate,
        **_decode_options(_D["min_modulation"], 0.0, no_nonlinearity, phase_filter, whole_residual_sigma)}
    if opts["max_depth"] <= opts["min_depth"]:
        raise check.fail("max_depth", f"must exceed min_depth ({opts['min_depth']:g} mm)")
    if opts["phase_filter"] > 6:
        raise check.fail("phase_filter", f"at most 6 px, got {opts['phase_filter']}")
    return opts


def scan(source: Union[PathLike, Frames], right_frames: Optional[Frames] = None,
         calibration: Union[None, PathLike, _core.StereoCalibration] = None,
         sequence: Optional[SequenceLike] = None, *, radius: float = 19.05, fix_radius: bool = False,
         spheres: int = 1, min_depth: float = 100.0, max_depth: float = 10000.0, phase_filter: int = 0,
         roi: str = "full", roi_margin: float = _D["roi_margin"], roi_stride: int = 0, no_nonlinearity: bool = False,
         whole_residual_sigma: bool = False, lr_sigma_factor: float = _D["lr_sigma_factor"],
         load_whole_frames: bool = False, full_scale: Optional[float] = None,
         noise_term: bool = True, kernel_estimate: str = "off",
         progress: Optional[ProgressFn] = None) -> ScanResult:
    """Scans a stereo fringe set (`ramtk scan`; keyword options named as its command-line options).

    source: a manifest path, or the left camera's frames in memory (2-D uint8 / uint16 / float32
        arrays in the sequence's order, e.g. from cv2.imread(path, cv2.IMREAD_UNCHANGED)); then
        right_frames, calibration and sequence are needed.
    calibration: a stereo calibration file or ramtk.StereoCalibration (default: the manifest's).
    sequence: the pattern sequence of in-memory frames: a manifest path or dict.
    radius: sphere radius prior, mm (0 = unknown); fix_radius holds it. spheres: how many to find.
    min_depth, max_depth: the epipolar search range, mm.
    phase_filter: smoothing window half-width of the decoded coordinate, px (0 = off, at most 6).
    roi: 'full', 'auto' (a coarse pass finds the ball, then windows around it) or 'X,Y,Z' (a
        predicted ball_in_left_camera, mm); roi_margin: mm added to the radius for the window;
        roi_stride: the coarse pass's pixel stride (0 = automatic).
    noise_term: move each match by the noise's second-order term (`--no-noise-term` turns it off).
    kernel_estimate: 'off' or 'auto': estimate the cameras' sampling kernel from the data when the
        calibration states none, and apply the matcher's kernel terms with it (`--kernel-estimate`).
    progress: progress(stage, done, total) after each stage; return False to cancel (the result's
        termination is then "cancelled"). Ctrl-C raises KeyboardInterrupt at the next stage.
    Returns the cloud (mm, left-camera frame, σ per point), the depth map (mm) and the spheres.
    """
    opts = scan_options(radius=radius, fix_radius=fix_radius, spheres=spheres, min_depth=min_depth,
                        max_depth=max_depth, phase_filter=phase_filter, roi=roi, roi_margin=roi_margin,
                        roi_stride=roi_stride, no_nonlinearity=no_nonlinearity,
                        whole_residual_sigma=whole_residual_sigma, lr_sigma_factor=lr_sigma_factor,
                        load_whole_frames=load_whole_frames, noise_term=noise_term,
                        kernel_estimate=kernel_estimate)
    if progress is not None and not callable(progress):
        raise check.fail("progress", "expected a callable progress(stage, done, total)")
    keep: List[Any] = []
    if isinstance(source, (str, os.PathLike)):
        opts["calibration"] = _calibration_path(calibration, keep)
        data = _core.scan(os.fspath(source), opts, progress)
    else:
        left = check.frames(source, "left_frames")
        right = check.frames(right_frames, "right_frames")
        if calibration is None:
            raise check.fail("calibration", "frames in memory need the stereo calibration (a path or object)")
        cal = calibration if isinstance(calibration, _core.StereoCalibration) else \
            _core.StereoCalibration.read(check.path(calibration, "calibration"))
        cal_path = "" if isinstance(calibration, _core.StereoCalibration) else os.fspath(calibration)
        text, where = _sequence(sequence)
        if left[0].dtype != right[0].dtype:
            raise check.fail("right_frames", f"dtype {right[0].dtype} beside left frames of {left[0].dtype}")
        data = _core.scan_frames(left, right, cal, cal_path, text, where, check.full_scale(full_scale, left[0]),
                                 opts, progress)
    return _scan_result(data)


def _scan_result(data: Any) -> ScanResult:
    return ScanResult(cloud=Cloud(data.points, data.sigma_mm, data.quality), depth_mm=data.depth,
                      spheres=[Sphere(**s) for s in data.spheres], termination=data.termination,
                      report=data.report, summary=data.summary, _data=data)


def fit_sphere(points: npt.ArrayLike, sigma: Optional[npt.ArrayLike] = None, *, radius: float = 0.0,
               fix_radius: bool = False, spheres: int = 1, seed: int = 1, min_points: int = 200) -> List[Sphere]:
    """Finds up to `spheres` spheres in an N×3 cloud (mm): RANSAC with the radius prior (mm, 0 =
    unknown), then a robust fit, σ-weighted when `sigma` (mm, one per point) is given."""
    p = check.float_array(points, "points")
    if p.ndim != 2 or p.shape[1] != 3:
        raise check.fail("points", f"expected an N×3 array, got shape {p.shape}")
    s = None
    if sigma is not None:
        s = check.float_array(sigma, "sigma")
        if s.shape != (p.shape[0],):
            raise check.fail("sigma", f"expected one σ per point ({p.shape[0]}), got shape {s.shape}")
        if (s <= 0).any():
            raise check.fail("sigma", f"element {int(np.argmax(s <= 0))} is not positive")
    out = _core.fit_sphere(np.ascontiguousarray(p), s, check.number(radius, "radius", 0.0),
                           check.flag(fix_radius, "fix_radius"), check.count(spheres, "spheres", 1),
                           check.count(seed, "seed", 0), check.count(min_points, "min_points", 4))
    return [Sphere(**d) for d in out]


def simulate_fringe(out: PathLike, *, preset: str = "small", seed: int = 1, noise: bool = True,
                    supersampling: int = 4, force: bool = False, frame_format: str = "png",
                    progress: Optional[ProgressFn] = None) -> FringeSet:
    """Renders a stereo fringe set of the 38.1 mm ball into `out` (`ramtk simulate fringe`);
    frame_format 'png' or 'bmp' (8-bit uncompressed, read by rows under scan's roi)."""
    d = _core.simulate_fringe(check.path(out, "out"), preset, check.count(seed, "seed", 0),
                              check.flag(noise, "noise"), check.count(supersampling, "supersampling", 1),
                              check.flag(force, "force"), frame_format, progress)
    return as_type(FringeSet, d)

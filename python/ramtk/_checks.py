"""Argument checks of the Python layer: bad input raises ramtk.InputError (a ValueError) naming
the argument, before anything reaches the C++ library. Never NaN out, never a crash."""
from __future__ import annotations

import math
import numbers
import os
from typing import Any, List, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._core import InputError

PathLike = Union[str, "os.PathLike[str]"]
FloatArray = npt.NDArray[np.float64]

# Joint angles beyond three turns are refused (the measurement reader's limit): a radian value
# or a corrupt row, never a controller reading.
MAX_ABS_JOINT_DEG = 1080.0
# Largest |RᵀR − I| accepted for the rotation part of a pose (the calibration reader's limit).
MAX_ORTHONORMALITY_ERROR = 1e-6
FRAME_DTYPES = (np.dtype(np.uint8), np.dtype(np.uint16), np.dtype(np.float32))


def fail(field: str, message: str) -> InputError:
    """An InputError naming `field` (its attributes as those raised by the C++ library)."""
    error = InputError(f"{field}: {message}")
    error.file, error.line, error.field, error.message = "", 0, field, message
    return error


def path(value: Any, field: str) -> str:
    if not isinstance(value, (str, os.PathLike)):
        raise fail(field, f"expected a path, got {type(value).__name__}")
    return os.fspath(value)


def float_array(value: Any, field: str) -> FloatArray:
    if isinstance(value, (str, bytes)):
        raise fail(field, "expected numbers, got a string")
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise fail(field, f"expected numbers ({e})") from None
    bad = ~np.isfinite(a)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        raise fail(field, f"element {where if len(where) > 1 else where[0]} is not finite ({a[bad][0]})")
    return a


def joints(value: Any, field: str = "q_deg") -> Tuple[FloatArray, bool]:
    """(N×6 joint angles in degrees, True if one joint set was given)."""
    a = float_array(value, field)
    single = a.ndim == 1
    if single:
        a = a.reshape(1, -1)
    if a.ndim != 2 or a.shape[1] != 6:
        raise fail(field, f"expected 6 joint angles (deg) or an N×6 array, got shape {np.shape(value)}")
    big = np.abs(a) > MAX_ABS_JOINT_DEG
    if big.any():
        row, col = (int(i) for i in np.argwhere(big)[0])
        raise fail(field, f"joint {col + 1} of row {row} is {a[row, col]} deg, beyond ±{MAX_ABS_JOINT_DEG:g} deg")
    return np.ascontiguousarray(a), single


def vector(value: Any, field: str, size: int) -> FloatArray:
    a = float_array(value, field)
    if a.shape != (size,):
        raise fail(field, f"expected {size} values, got shape {a.shape}")
    return a


def pose(value: Any, field: str = "pose") -> FloatArray:
    """A 4×4 rigid transform (rotation and translation in mm), checked."""
    a = float_array(value, field)
    if a.shape != (4, 4):
        raise fail(field, f"expected a 4×4 array, got shape {a.shape}")
    if np.abs(a[3] - [0, 0, 0, 1]).max() > 1e-12:
        raise fail(field, f"the last row is {a[3].tolist()}, not [0, 0, 0, 1]")
    r = a[:3, :3]
    error = float(np.abs(r.T @ r - np.eye(3)).max())
    if error > MAX_ORTHONORMALITY_ERROR or np.linalg.det(r) < 0:
        raise fail(field, f"not a rigid transform: the rotation part has |RᵀR − I| = {error:.3g} "
                   f"(at most {MAX_ORTHONORMALITY_ERROR:g}) and det {np.linalg.det(r):.6g}")
    return a


def count(value: Any, field: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise fail(field, f"expected an integer, got {type(value).__name__}")
    if value < minimum:
        raise fail(field, f"must be >= {minimum}, got {value}")
    return int(value)


def number(value: Any, field: str, minimum: float = -math.inf, strict: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise fail(field, f"expected a number, got {type(value).__name__}")
    v = float(value)
    if not math.isfinite(v):
        raise fail(field, f"is not finite ({v})")
    if v < minimum or (strict and v == minimum):
        raise fail(field, f"must be {'>' if strict else '>='} {minimum:g}, got {v:g}")
    return v


def flag(value: Any, field: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise fail(field, f"expected True or False, got {type(value).__name__}")
    return bool(value)


def frames(value: Any, field: str) -> List[npt.NDArray[Any]]:
    """A camera's frames: 2-D, C-contiguous uint8 / uint16 / float32 arrays of one size (viewed by
    the C++ library without a copy)."""
    if isinstance(value, np.ndarray) and value.ndim == 3:
        value = list(value)
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)) or len(value) == 0:
        raise fail(field, "expected a non-empty list of 2-D image arrays")
    out: List[npt.NDArray[Any]] = []
    for i, f in enumerate(value):
        name = f"{field}[{i}]"
        if not isinstance(f, np.ndarray):
            raise fail(name, f"expected a numpy array, got {type(f).__name__}")
        if f.ndim != 2:
            raise fail(name, f"expected a single-channel 2-D image, got shape {f.shape} "
                       "(cv2.imread(path, cv2.IMREAD_UNCHANGED) keeps grey frames grey)")
        if f.dtype not in FRAME_DTYPES:
            raise fail(name, f"dtype {f.dtype}: expected uint8, uint16 or float32")
        if not f.flags["C_CONTIGUOUS"]:
            raise fail(name, "not C-contiguous (a slice or transpose): pass np.ascontiguousarray(frame)")
        if f.shape != value[0].shape or f.dtype != value[0].dtype:
            raise fail(name, f"{f.shape} {f.dtype} differs from {field}[0] {value[0].shape} {value[0].dtype}")
        out.append(f)
    return out


def full_scale(given: Any, sample: npt.NDArray[Any], field: str = "full_scale") -> float:
    """The frames' full scale: 255 for uint8, 65535 for uint16 (as the file reader), given for float32."""
    if given is not None:
        return number(given, field, 0.0, strict=True)
    if sample.dtype == np.uint8:
        return 255.0
    if sample.dtype == np.uint16:
        return 65535.0
    raise fail(field, "float32 frames need their full scale (DN)")

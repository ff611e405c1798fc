"""Robot measurement tables from memory: a dict of columns, a numpy structured array or a plain
2-D array become the CSV text of docs/formats.md, which the C++ file reader then checks as it
checks a file (errors name the argument, line = row + 2)."""
from __future__ import annotations

import os
from typing import Any, Dict, List, Mapping, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _checks as check

# cycle,time_s,pose|point,q1..q6,x,y,z (joints in degrees, positions in mm), then optionally the
# centre covariance (mm²) cov_xx cov_yy cov_zz cov_xy cov_xz cov_yz.
JOINTS = [f"q{i}" for i in range(1, 7)]
COVARIANCE = ["cov_xx", "cov_yy", "cov_zz", "cov_xy", "cov_xz", "cov_yz"]
BALL_COLUMNS = ["cycle", "time_s", "pose", *JOINTS, "x", "y", "z"]
INTEGER_COLUMNS = {"cycle", "pose", "point"}

Table = Union[str, "os.PathLike[str]", Mapping[str, npt.ArrayLike], npt.NDArray[Any]]


def _columns(table: Any, field: str) -> Dict[str, npt.NDArray[np.float64]]:
    if isinstance(table, np.ndarray) and table.dtype.names:
        table = {n: table[n] for n in table.dtype.names}
    if isinstance(table, np.ndarray):
        a = check.float_array(table, field)
        if a.ndim != 2 or a.shape[1] not in (12, 18):
            raise check.fail(field, f"a plain array needs 12 columns ({','.join(BALL_COLUMNS)}) or 18 (then "
                             f"{','.join(COVARIANCE)}), got shape {a.shape}")
        names = BALL_COLUMNS + (COVARIANCE if a.shape[1] == 18 else [])
        return {n: a[:, i] for i, n in enumerate(names)}
    if not isinstance(table, Mapping):
        raise check.fail(field, f"expected a CSV path, a dict of columns or an array, got {type(table).__name__}")
    cols: Dict[str, npt.NDArray[np.float64]] = {}
    for name, values in table.items():
        key = f"{field}[{name!r}]"
        a = check.float_array(values, key)
        if name == "q_deg":  # N×6 joints
            if a.ndim != 2 or a.shape[1] != 6:
                raise check.fail(key, f"expected N×6 joint angles (deg), got shape {a.shape}")
            cols.update({q: a[:, i] for i, q in enumerate(JOINTS)})
        elif name in ("xyz_mm", "ball_mm", "point_mm"):  # N×3 positions
            if a.ndim != 2 or a.shape[1] != 3:
                raise check.fail(key, f"expected N×3 positions (mm), got shape {a.shape}")
            cols.update({c: a[:, i] for i, c in enumerate("xyz")})
        elif name == "covariance_mm2":  # N×3×3
            if a.ndim != 3 or a.shape[1:] != (3, 3):
                raise check.fail(key, f"expected N×3×3 covariances (mm²), got shape {a.shape}")
            pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]
            cols.update({c: a[:, i, j] for c, (i, j) in zip(COVARIANCE, pairs)})
        else:
            if a.ndim != 1:
                raise check.fail(key, f"expected a column (1-D), got shape {a.shape}")
            cols[str(name)] = a
    return cols


def table_text(table: Any, field: str) -> str:
    cols = _columns(table, field)
    missing = [c for c in [*JOINTS, "x", "y", "z"] if c not in cols]
    if missing:
        raise check.fail(field, f"missing column(s) {', '.join(missing)} (joints q1..q6 in deg or 'q_deg' N×6; "
                         "x, y, z in mm or 'xyz_mm' N×3)")
    n = len(cols["q1"])
    if n == 0:
        raise check.fail(field, "no rows")
    for name, a in cols.items():
        if len(a) != n:
            raise check.fail(f"{field}[{name!r}]", f"{len(a)} rows beside {n} of q1")
        if name in INTEGER_COLUMNS and (a != np.round(a)).any():
            raise check.fail(f"{field}[{name!r}]", f"row {int(np.argmax(a != np.round(a)))} is not an integer")
    cols.setdefault("cycle", np.zeros(n))
    cols.setdefault("time_s", np.zeros(n))
    if "pose" not in cols and "point" not in cols:
        cols["pose"] = np.arange(n, dtype=np.float64)
    index = "point" if "point" in cols else "pose"
    names: List[str] = ["cycle", "time_s", index, *JOINTS, "x", "y", "z"]
    names += [c for c in cols if c not in names]
    lines = [",".join(names)]
    formats = ["{:d}" if c in INTEGER_COLUMNS else "{!r}" for c in names]
    data = [cols[c].astype(np.int64).tolist() if c in INTEGER_COLUMNS else cols[c].tolist() for c in names]
    for row in zip(*data):
        lines.append(",".join(f.format(v) for f, v in zip(formats, row)))
    return "\n".join(lines) + "\n"


def table_source(table: Table, field: str) -> Tuple[str, str]:
    """(the file path, "") for a path; (a label naming the argument, CSV text) for a table in memory."""
    if isinstance(table, (str, os.PathLike)):
        return os.fspath(table), ""
    return f"<{field}>", table_text(table, field)


def measurement_table(table: Table) -> str:
    """The CSV text (docs/formats.md) of a measurement table given as columns or an array."""
    return table_text(table, "table") if not isinstance(table, (str, os.PathLike)) else open(table).read()

"""Thermal drift: the thesis simulator, identification of ΔX per cycle and parameter screening,
from measurement files or tables in memory (docs/thermal.md)."""
from __future__ import annotations

import os
from typing import Optional, Sequence, Union

import numpy as np

from . import _checks as check
from . import _core
from ._results import DriftEstimate, Screening, ThermalSimulation, as_type
from ._robot import RobotLike, robot_model
from ._tables import Table, table_source

PathLike = Union[str, "os.PathLike[str]"]
_D = _core.defaults()


def simulate_thermal(robot: RobotLike, out: PathLike, *, seed: int = 1, cycles: Optional[int] = None,
                     force: bool = False) -> ThermalSimulation:
    """The thesis thermal experiment (`ramtk simulate thermal`): writes ball.csv, monitoring.csv,
    setup.json and the truth into `out`; cycles: warm-up cycles (default: the thesis's 90)."""
    n = 0 if cycles is None else check.count(cycles, "cycles", 1)
    d = _core.simulate_thermal(robot_model(robot), check.path(out, "out"), check.count(seed, "seed", 0), n,
                               check.flag(force, "force"))
    return as_type(ThermalSimulation, d)


def thermal_identify(robot: RobotLike, setup: PathLike, ball: Table, params: Sequence[str]) -> DriftEstimate:
    """ΔX of the named parameters (ramtk.PARAM_NAMES) per cycle (thesis eq. 3-8) from the ball
    measurements (a CSV path, a dict of columns or an array; a `cycle` column groups them)."""
    if isinstance(params, str) or not all(isinstance(p, str) for p in params) or not params:
        raise check.fail("params", "expected a non-empty list of parameter names, e.g. ['d1', 'a2']")
    source, text = table_source(ball, "ball")
    d = _core.thermal_identify(robot_model(robot), check.path(setup, "setup"), source, text, list(params))
    d["params"] = list(params)
    d["delta_x"] = np.asarray(d["delta_x"])
    return as_type(DriftEstimate, d)


def thermal_screen(robot: RobotLike, setup: PathLike, ball: Table, monitoring: Table, *,
                   keep: int = _D["screen_keep"], heldout_z: float = _D["screen_heldout_z"]) -> Screening:
    """Screens the drifting parameters (thesis §3.2): keep = 0 chooses the count by held-out error;
    heldout_z: how many held-out σ a removal may cost."""
    b_source, b_text = table_source(ball, "ball")
    m_source, m_text = table_source(monitoring, "monitoring")
    d = _core.thermal_screen(robot_model(robot), check.path(setup, "setup"), b_source, b_text, m_source, m_text,
                             check.count(keep, "keep", 0), check.number(heldout_z, "heldout_z", 0.0))
    return as_type(Screening, d)

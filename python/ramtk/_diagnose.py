"""`ramtk diagnose`: what the simulation gets wrong on measured data (docs/diagnose.md)."""
from __future__ import annotations

import os
from typing import Sequence, Union

from . import _checks as check
from . import _core
from ._results import Diagnosis

PathLike = Union[str, "os.PathLike[str]"]
_D = _core.defaults()


def diagnose(data: PathLike, *, model: str = "", with_: Sequence[str] = (), out: str = "",
             folds: int = _D["diagnose_folds"], noise: float = _D["diagnose_noise"],
             alpha: float = _D["diagnose_alpha"], seed: int = _D["diagnose_seed"]) -> Diagnosis:
    """Diagnoses a fringe manifest, a robot measurement CSV or a laser log against the model;
    with_: causes to try besides the catalogue's; out: a folder for report.md and diagnosis.json."""
    d = _core.diagnose(check.path(data, "data"), model, [str(w) for w in with_], out,
                       check.count(folds, "folds", 2), check.number(noise, "noise", 0.0),
                       check.number(alpha, "alpha", 0.0, True), check.count(seed, "seed", 0))
    one_line = d.pop("one_line")
    report_md = d.pop("report_md", None)
    diagnosis_json = d.pop("diagnosis_json", None)
    return Diagnosis(one_line=one_line, data=d, report_md=report_md, diagnosis_json=diagnosis_json)

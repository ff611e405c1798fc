"""Data shipped with the package: the robot models of datasets/robots (BX200L, KR150, UR10)."""
from __future__ import annotations

import os
from typing import List

DATA_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")


def robots() -> List[str]:
    """Names of the shipped robot models (for ramtk.robot_path)."""
    return sorted(f[:-5] for f in os.listdir(os.path.join(DATA_DIR, "robots")) if f.endswith(".yaml"))


def robot_path(name: str) -> str:
    """The installed YAML of a shipped robot model, e.g. robot_path('kuka_kr150_r3100')."""
    p = os.path.join(DATA_DIR, "robots", name + ".yaml")
    if not os.path.isfile(p):
        from ._checks import fail

        raise fail("name", f"no shipped robot '{name}'; shipped: {', '.join(robots())}")
    return p

"""Thermal simulation, identification, screening, sensor-to-robot calibration and diagnosis
against the ramtk command on the same files and against the simulator's truth."""
import json

import numpy as np
import pytest

import ramtk


@pytest.fixture(scope="module")
def thermal(datasets, scratch):
    robot = str(datasets / "robots" / "kuka_kr150_r3100.yaml")
    out = scratch / "thermal"
    truth = ramtk.simulate_thermal(robot, str(out), seed=3, cycles=30, force=True)
    return robot, out, truth


def test_simulate_thermal_writes_the_command_files(thermal):
    robot, out, truth = thermal
    for f in ("ball.csv", "monitoring.csv", "setup.json", "truth.json", "truth_params.csv"):
        assert (out / f).exists(), f
    assert truth.drifting_params == ["d4", "d6", "a1", "a2", "a3", "alpha3", "alpha4", "beta2"]
    assert truth.true_delta_x.shape == (30, 30)


def test_identify_matches_the_command_and_the_truth(thermal, cli):
    robot, out, truth = thermal
    params = truth.drifting_params
    r = ramtk.thermal_identify(robot, str(out / "setup.json"), str(out / "ball.csv"), params)
    csv = out / "dx.csv"
    cli("thermal", "identify", "--robot", robot, "--setup", out / "setup.json", "--ball", out / "ball.csv",
        "--params", ",".join(params), "--out", csv)
    table = np.genfromtxt(csv, delimiter=",", names=True)
    for i, p in enumerate(params):
        python_value = r.delta_x[i]
        file_value = table[p] if p.startswith(("d", "a")) and not p.startswith("alpha") else np.radians(table[p])
        np.testing.assert_allclose(python_value, file_value, rtol=1e-6, atol=1e-9)
    assert r.rank == len(params)


def test_screen_keeps_drifting_parameters(thermal):
    robot, out, truth = thermal
    s = ramtk.thermal_screen(robot, str(out / "setup.json"), str(out / "ball.csv"), str(out / "monitoring.csv"))
    assert set(s.selected) <= set(truth.drifting_params)
    assert s.final_lambda_percent >= 95.0
    assert "held-out" in s.table


def test_sensor_robot_calibration_against_truth(cli, datasets, scratch):
    robot = str(datasets / "robots" / "kuka_kr150_r3100.yaml")
    m, t = scratch / "sr.csv", scratch / "sr_truth.json"
    cli("simulate", "sensor-robot", "--robot", robot, "--output", m, "--truth", t, "--poses", 12)
    r = ramtk.calibrate_sensor_robot(robot, str(m))
    assert r.converged
    truth = json.loads(t.read_text())
    key = next(k for k in truth if "ball_in_flange" in k)
    err = np.asarray(r.ball_in_flange_mm) - np.asarray(truth[key])
    assert (np.abs(err) < 5 * np.asarray(r.ball_std_mm) + 1e-6).all()


def test_diagnose_matches_the_command(thermal, cli, scratch):
    robot, out, truth = thermal
    d = ramtk.diagnose(str(out / "ball.csv"), model="kr150", with_=[str(out / "setup.json")],
                       out=str(scratch / "diag_py"))
    line = cli("diagnose", out / "ball.csv", "--model", "kr150", "--with", out / "setup.json", "--out",
               scratch / "diag_cli", "--force").splitlines()[0]
    assert d.one_line == line
    assert json.loads((scratch / "diag_py" / "diagnosis.json").read_text())["cause"] == d.data["cause"]

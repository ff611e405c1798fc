"""Batch scans with shards, merge, measure, the campaign twin, the robot calibration and hand-eye
against the ramtk command on the same files, and hand-eye against a closed-form truth."""
import csv
import io
import json

import numpy as np
import pytest

import ramtk


@pytest.fixture(scope="module")
def campaign(scratch):
    out = scratch / "campaign"
    r = ramtk.simulate_campaign(ramtk.robot_path("kuka_kr150_r3100"), out, cycles=2, points=3, force=True)
    return out, r


def rows(text, drop=("seconds", "out_dir")):
    return [{k: v for k, v in row.items() if k not in drop} for row in csv.DictReader(io.StringIO(text))]


def test_campaign_budget_is_written_and_returned(campaign):
    out, r = campaign
    assert not r.cancelled and r.left_out == []
    written = json.loads((out / "budget.json").read_text())
    assert written.pop("provenance")["command"] == ["python", "ramtk.simulate_campaign"]
    assert r.budget == written
    assert (out / "budget.md").read_text().startswith(r.budget_md + "\n## Provenance")


def test_sharded_batch_and_merge_give_the_commands_results(campaign, cli, scratch):
    out, _ = campaign
    batch = out / "batch.txt"
    shards = scratch / "batch_py"
    a = ramtk.scan_batch(batch, shards, shard="1/2", force=True, roi="auto")
    b = ramtk.scan_batch(batch, shards, shard="2/2", force=True, roi="auto")
    assert a.sets + b.sets == 16 and a.ok + b.ok == 16
    merged = ramtk.merge(batch, shards, force=True)
    cli("scan", "--batch", batch, "--out", scratch / "batch_cli", "--roi", "auto", "--force", "-q")
    expected = (scratch / "batch_cli" / "results.csv").read_text()
    assert rows(open(merged).read()) == rows(expected)
    # A second run without force or resume changes nothing and says why.
    with pytest.raises(ramtk.InputError, match="resume"):
        ramtk.scan_batch(batch, shards, shard="1/2", roi="auto")
    # resume keeps every set the first run finished (their rows, wall times included, come back).
    again = ramtk.scan_batch(batch, shards, shard="1/2", resume=True, roi="auto")
    assert rows(again.csv, drop=("out_dir",)) == rows(a.csv, drop=("out_dir",))
    # The same settings string as the command: a resume from Python keeps the command's sets.
    kept = ramtk.scan_batch(batch, scratch / "batch_cli", resume=True, roi="auto")
    assert rows(kept.csv, drop=("out_dir",)) == rows(expected, drop=("out_dir",))


def test_measure_gives_the_commands_table(campaign, cli, scratch):
    out, _ = campaign
    results = scratch / "batch_cli" / "results.csv"
    if not results.exists():
        cli("scan", "--batch", out / "batch.txt", "--out", scratch / "batch_cli", "--roi", "auto", "--force", "-q")
    cli("measure", "--scans", results, "--log", out / "controller_log.csv", "--out", scratch / "ball_cli.csv")
    m = ramtk.measure(results, out / "controller_log.csv")
    assert m.table == (scratch / "ball_cli.csv").read_text()
    assert m.written == 16 and m.columns["x"].shape == (16,) and "cov_xx" in m.columns
    # The table feeds the calibration directly (columns in memory).
    robot = ramtk.robot_path("kuka_kr150_r3100")
    cold = {k: v[m.columns["cycle"] == m.columns["cycle"].min()] for k, v in m.columns.items()}
    cal = ramtk.calibrate_sensor_robot(robot, cold)
    assert cal.converged and cal.rms_mm < 0.1


def test_robot_calibration_matches_the_command(cli, scratch):
    robot = ramtk.robot_path("kuka_kr150_r3100")
    data, truth = scratch / "tracker.csv", scratch / "tracker_truth.yaml"
    cli("simulate", "robot-calibration", "--robot", robot, "--output", data, "--truth", truth, "--poses", 60)
    cli("calib", "robot", "--robot", robot, "--data", data, "--out", scratch / "calib_cli", "--force")
    steps = []
    r = ramtk.calibrate_robot(robot, data, out=scratch / "calib_py", force=True,
                              progress=lambda stage, done, total: steps.append(stage))
    expected = json.loads((scratch / "calib_cli" / "calibration.json").read_text())
    written = json.loads((scratch / "calib_py" / "calibration.json").read_text())
    assert written.pop("provenance")["inputs"][1]["xxh3_128"] == expected.pop("provenance")["inputs"][1]["xxh3_128"]
    assert r.calibration == expected == written
    assert (scratch / "calib_py" / "robot.yaml").read_text().split("\n", 3)[3] == \
        (scratch / "calib_cli" / "robot.yaml").read_text().split("\n", 3)[3]
    assert r.rms_after_mm < r.rms_before_mm and r.termination in ("success", "partial")
    assert steps, "no progress reported"
    with pytest.raises(ramtk.InputError) as e:
        ramtk.calibrate_robot(robot, data, loss="l1")
    assert e.value.field == "loss"


def rot(axis, deg):
    a = np.radians(deg)
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * kx + (1 - np.cos(a)) * kx @ kx


def pose(r, t):
    p = np.eye(4)
    p[:3, :3], p[:3, 3] = r, t
    return p


def test_hand_eye_recovers_a_noise_free_truth():
    # camera_from_board_i = camera_from_base · base_from_flange_i · flange_from_board (closed form).
    robot = ramtk.RobotModel.read(ramtk.robot_path("kuka_kr150_r3100"))
    rng = np.random.default_rng(2)
    flanges = ramtk.fk(robot, np.array([10, -80, 100, 0, 30, 0]) + rng.uniform(-30, 30, size=(10, 6)))
    camera_from_base = pose(rot([0.2, 1, 0.1], 160), [300, -200, 2500])
    flange_from_board = pose(rot([1, 0, 0.3], 20), [0, 40, 120])
    boards = camera_from_base @ flanges @ flange_from_board
    r = ramtk.hand_eye(flanges, boards)
    np.testing.assert_allclose(r.camera_from_base, camera_from_base, atol=1e-6)
    np.testing.assert_allclose(r.flange_from_board, flange_from_board, atol=1e-6)
    assert r.rms_translation_mm < 1e-6
    with pytest.raises(ramtk.InputError) as e:  # one rotation for every pose: degenerate
        ramtk.hand_eye(np.repeat(flanges[:1], 10, axis=0), boards)
    assert e.value.field == "poses"
    bent = boards.copy()
    bent[3, :3, :3] *= 1.01
    with pytest.raises(ramtk.InputError) as e:
        ramtk.hand_eye(flanges, bent)
    assert e.value.field == "camera_from_board[3]"


def test_campaign_arguments_are_checked(scratch):
    for kwargs, field in (({"cycles": 1}, "cycles"), ({"poses": 3}, "poses"), ({"scale": 2.0}, "scale"),
                          ({"jobs": 0}, "jobs")):
        with pytest.raises(ramtk.InputError) as e:
            ramtk.simulate_campaign(ramtk.robot_path("ur10"), scratch / "never", **kwargs)
        assert e.value.field == field

"""Robot models, FK, the parameter Jacobian and IK against the ramtk command and closed forms."""
import json

import numpy as np
import pytest

import ramtk


def test_version_matches_the_command(cli):
    assert cli("--version").strip() == f"ramtk {ramtk.__version__}"


def test_fk_matches_the_command(cli, datasets):
    robot = datasets / "robots" / "kawasaki_bx200l.yaml"
    q = [90, 10, -20, 30, 40, 50]
    expected = json.loads(cli("fk", "--robot", robot, "--joints", ",".join(map(str, q)), "--json"))
    t = ramtk.fk(ramtk.RobotModel.read(str(robot)), q)
    assert t.shape == (4, 4)
    np.testing.assert_allclose(t[:3, 3], expected["base_from_flange"]["position_mm"], atol=1e-9)
    np.testing.assert_allclose(t, expected["base_from_flange"]["matrix"], atol=1e-12)
    np.testing.assert_allclose(t[3], [0, 0, 0, 1])


def test_point_jacobian_columns_of_d1_and_a1(datasets):
    # Closed forms: a change of d1 moves every point along the base Z axis; a change of a1 moves it
    # along link 1's X axis, which for MDH is the base X axis turned by θ1 (q1 = 0 here: base X).
    model = ramtk.RobotModel.read(str(datasets / "robots" / "kuka_kr150_r3100.yaml"))
    j = ramtk.point_jacobian(model, [0, -90, 90, 0, 30, 0], [0, 0, 150])
    assert j.shape == (3, 30)
    names = ramtk.PARAM_NAMES
    np.testing.assert_allclose(j[:, names.index("d1")], [0, 0, 1], atol=1e-12)
    col = j[:, names.index("a1")]
    assert abs(np.linalg.norm(col) - 1) < 1e-12 and abs(col[2]) < 1e-12


def test_ik_returns_to_the_pose(datasets):
    model = ramtk.RobotModel.read(str(datasets / "robots" / "kuka_kr150_r3100.yaml"))
    q = [20, -80, 100, 10, 40, -30]
    target = ramtk.fk(model, q)
    r = ramtk.ik(model, target, [15, -85, 95, 5, 35, -25])
    assert r.converged, r.report
    np.testing.assert_allclose(ramtk.fk(model, r.q_deg), target, atol=1e-6)


def test_bad_input_raises_input_error_naming_the_file(scratch):
    bad = scratch / "bad_robot.yaml"
    bad.write_text("name: x\nlinks: 3\n")
    with pytest.raises(ramtk.InputError) as e:
        ramtk.RobotModel.read(str(bad))
    assert isinstance(e.value, ValueError)
    assert e.value.file == str(bad)
    assert str(bad) in str(e.value)


def test_wrong_joint_count_names_the_argument(datasets):
    model = ramtk.RobotModel.read(str(datasets / "robots" / "ur10.yaml"))
    with pytest.raises(ramtk.InputError) as e:
        ramtk.fk(model, [0, 0, 0])
    assert e.value.field == "q_deg"

"""The package surface: scans and decodes of frames in memory against the command on the files
(byte-identical cloud.ply), batch kinematics against the command and closed forms, progress and
Ctrl-C, measurement tables in memory against the same file, typed results, bad input."""
import json
import os
import signal

import numpy as np
import pytest

import ramtk

try:
    import cv2
except ImportError:  # the module's own reader then loads the frames as stored
    cv2 = None


def load_frames(paths):
    if cv2 is not None:
        return [cv2.imread(p, cv2.IMREAD_UNCHANGED) for p in paths]
    return [ramtk.read_image(p) for p in paths]


@pytest.fixture(scope="module")
def default_set(datasets):
    return str(datasets / "scan_default" / "manifest.json")


@pytest.fixture(scope="module")
def frames(default_set):
    m = ramtk.read_manifest(default_set)
    return load_frames(m["resolved_images"]["left"]), load_frames(m["resolved_images"]["right"])


@pytest.fixture(scope="module")
def robot(datasets):
    return ramtk.RobotModel.read(str(datasets / "robots" / "kuka_kr150_r3100.yaml"))


def test_scan_of_frames_in_memory_writes_the_commands_cloud(cli, default_set, frames, datasets, scratch):
    left, right = frames
    assert left[0].dtype == np.uint8 and left[0].ndim == 2
    cal = str(datasets / "scan_default" / "calibration.yml")
    r = ramtk.scan(left, right, cal, default_set)
    cli("scan", default_set, "--out", scratch / "ply_cli", "--force")
    r.write(scratch / "ply_py", set_label=default_set, force=True)
    assert (scratch / "ply_py" / "cloud.ply").read_bytes() == (scratch / "ply_cli" / "cloud.ply").read_bytes()
    expected = json.loads((scratch / "ply_cli" / "spheres.json").read_text())["spheres"][0]["centre_mm"]
    np.testing.assert_array_equal(r.spheres[0].centre_mm, expected)
    # The same through a StereoCalibration object and the manifest as a dict.
    obj = ramtk.scan(left, right, ramtk.StereoCalibration.read(cal), ramtk.read_manifest(default_set))
    np.testing.assert_array_equal(obj.cloud.points_mm, r.cloud.points_mm)


def test_decode_of_frames_in_memory_equals_decode_of_the_files(default_set, frames):
    from_files = ramtk.decode(default_set, "left")
    in_memory = ramtk.decode(frames[0], "left", default_set)
    np.testing.assert_array_equal(in_memory.coordinate, from_files.coordinate)
    np.testing.assert_array_equal(in_memory.mask, from_files.mask)
    # float32 frames in DN with their full scale give the same coordinate (the 8-bit values are exact).
    as_float = [f.astype(np.float32) for f in frames[0]]
    f32 = ramtk.decode(as_float, "left", default_set, full_scale=255.0)
    np.testing.assert_allclose(f32.coordinate, from_files.coordinate, rtol=0, atol=1e-3, equal_nan=True)


def test_cloud_and_images_are_views_of_the_cpp_buffers(default_set):
    r = ramtk.scan(default_set, roi="auto")
    for a in (r.cloud.points_mm, r.cloud.sigma_mm, r.depth_mm):
        assert not a.flags["OWNDATA"] and a.base is not None
    assert r.cloud.points_mm.shape == (len(r.cloud), 3) and r.cloud.sigma_mm.shape == (len(r.cloud),)


def test_progress_names_each_stage_and_false_cancels(default_set):
    stages = []
    r = ramtk.scan(default_set, progress=lambda stage, done, total: stages.append((stage, done, total)))
    assert [s for s, _, _ in stages] == ["decode left", "decode right", "match", "triangulate", "fit"]
    assert stages[-1][1] == stages[-1][2]
    cancelled = ramtk.scan(default_set, progress=lambda stage, done, total: stage != "match")
    assert cancelled.termination == "cancelled" and len(cancelled.cloud) == 0 and r.termination == "success"


def test_ctrl_c_and_callback_errors_stop_the_scan(default_set):
    def interrupt(stage, done, total):
        os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        ramtk.scan(default_set, progress=interrupt)

    def broken(stage, done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        ramtk.scan(default_set, progress=broken)


def test_batch_fk_matches_the_command_row_by_row(cli, datasets, robot):
    rng = np.random.default_rng(11)
    q = rng.uniform(-90, 90, size=(5, 6))
    t = ramtk.fk(robot, q)
    assert t.shape == (5, 4, 4)
    for i in (0, 4):
        expected = json.loads(cli("fk", "--robot", datasets / "robots" / "kuka_kr150_r3100.yaml", "--joints",
                                  ",".join(repr(v) for v in q[i]), "--json"))
        np.testing.assert_allclose(t[i], expected["base_from_flange"]["matrix"], atol=1e-9)


def test_batch_point_jacobian_against_closed_forms(robot):
    # d1 moves every point along the base Z axis, for every joint set; a change of theta1's offset
    # turns the point about the base Z axis: column = z × p (p the point in the base frame, mm/rad).
    rng = np.random.default_rng(5)
    q = rng.uniform(-60, 60, size=(4, 6))
    p_flange = np.array([10.0, -20.0, 150.0])
    j = ramtk.point_jacobian(robot, q, p_flange)
    assert j.shape == (4, 3, 30)
    names = ramtk.PARAM_NAMES
    t = ramtk.fk(robot, q)
    for i in range(4):
        np.testing.assert_allclose(j[i][:, names.index("d1")], [0, 0, 1], atol=1e-12)
        p = t[i][:3, :3] @ p_flange + t[i][:3, 3]
        np.testing.assert_allclose(j[i][:, names.index("theta1")], np.cross([0, 0, 1], p), atol=1e-6)


def test_tables_in_memory_give_the_files_result(cli, datasets, scratch, robot):
    m, t = scratch / "table.csv", scratch / "table_truth.json"
    cli("simulate", "sensor-robot", "--robot", datasets / "robots" / "kuka_kr150_r3100.yaml", "--output", m,
        "--truth", t, "--poses", 12)
    from_file = ramtk.calibrate_sensor_robot(robot, m)
    table = np.genfromtxt(m, delimiter=",", names=True)
    columns = {name: table[name] for name in table.dtype.names}
    from_columns = ramtk.calibrate_sensor_robot(robot, columns)
    np.testing.assert_array_equal(from_columns.sensor_from_base, from_file.sensor_from_base)
    grouped = {"q_deg": np.column_stack([table[f"q{i}"] for i in range(1, 7)]),
               "xyz_mm": np.column_stack([table["x"], table["y"], table["z"]])}
    np.testing.assert_array_equal(ramtk.calibrate_sensor_robot(robot, grouped).ball_in_flange_mm,
                                  from_file.ball_in_flange_mm)
    plain = np.column_stack([table[c] for c in ["cycle", "time_s", "pose", *[f"q{i}" for i in range(1, 7)], "x", "y", "z"]])
    np.testing.assert_array_equal(ramtk.calibrate_sensor_robot(robot, plain).ball_in_flange_mm,
                                  from_file.ball_in_flange_mm)
    columns["x"] = columns["x"].copy()
    columns["x"][3] = np.nan
    with pytest.raises(ramtk.InputError, match=r"measurements\['x'\]"):
        ramtk.calibrate_sensor_robot(robot, columns)


def test_typed_results_print_briefly_and_serialise(default_set, robot):
    r = ramtk.scan(default_set, roi="auto")
    text = repr(r)
    assert text.startswith("ramtk.ScanResult(") and "float32 array" in text and len(text) < 1000
    sphere = json.loads(json.dumps(r.spheres[0].to_dict()))
    assert sphere["radius_mm"] == r.spheres[0].radius_mm and len(sphere["centre_covariance_mm2"]) == 3
    ik = ramtk.ik(robot, ramtk.fk(robot, [20, -80, 100, 10, 40, -30]), [15, -85, 95, 5, 35, -25])
    assert isinstance(ik, ramtk.IkSolution) and json.loads(json.dumps(ik.to_dict()))["converged"] is True


def test_stereo_calibration_is_constructed_and_shows_its_distortion(datasets):
    c = ramtk.StereoCalibration.read(str(datasets / "scan_default" / "calibration.yml"))
    assert len(c.left_distortion) == 5 and len(c.right_distortion) == 5
    d = ramtk.StereoCalibration(c.left_K, c.left_distortion, c.right_K, c.right_distortion, c.right_from_left,
                                c.image_size)
    np.testing.assert_array_equal(d.right_from_left, c.right_from_left)
    assert d.left_distortion == c.left_distortion and d.image_size == c.image_size
    bent = c.right_from_left.copy()
    bent[:3, :3] *= 2
    with pytest.raises(ramtk.InputError, match="R"):
        ramtk.StereoCalibration(c.left_K, c.left_distortion, c.right_K, c.right_distortion, bent, c.image_size)


def test_stereo_calibration_setters_check_like_the_file_reader(datasets, scratch):
    c = ramtk.StereoCalibration.read(str(datasets / "scan_default" / "calibration.yml"))
    c.left_distortion = [0.01, -0.002, 0.0001, 0.0, 0.0]
    k = c.right_K.copy()
    k[0, 2] += 1.5
    c.right_K = k
    c.write(str(scratch / "changed.yml"))
    back = ramtk.StereoCalibration.read(str(scratch / "changed.yml"))
    assert back.left_distortion == [0.01, -0.002, 0.0001, 0.0, 0.0]
    np.testing.assert_array_equal(back.right_K, k)
    before = c.right_from_left
    for name, value in (("right_from_left", 2 * np.eye(4)), ("left_K", np.array([[1, 0.5, 2], [0, 1, 2], [0, 0, 1]])),
                        ("left_distortion", [0.0, 0.0, 0.0]), ("right_distortion", [np.nan] * 5)):
        with pytest.raises(ramtk.InputError):
            setattr(c, name, value)
    np.testing.assert_array_equal(c.right_from_left, before)  # unchanged by a refused value


def bad(call, field):
    with pytest.raises(ramtk.InputError) as e:
        call()
    assert e.value.field.startswith(field), (e.value.field, str(e.value))
    assert isinstance(e.value, ValueError)


def test_bad_input_raises_naming_the_argument(robot, default_set, frames, datasets, scratch):
    left, right = frames
    cal = str(datasets / "scan_default" / "calibration.yml")
    bad(lambda: ramtk.fk(robot, [0, np.nan, 0, 0, 0, 0]), "q_deg")
    bad(lambda: ramtk.fk(robot, np.zeros((3, 5))), "q_deg")
    bad(lambda: ramtk.fk(robot, [0, 0, 0, 0, 0, 1e6]), "q_deg")
    bad(lambda: ramtk.point_jacobian(robot, np.full((2, 6), np.inf)), "q_deg")
    bad(lambda: ramtk.point_jacobian(robot, np.zeros(6), [0, 0]), "point_in_flange_mm")
    bad(lambda: ramtk.ik(robot, 2 * np.eye(4), np.zeros(6)), "pose")
    pose = np.eye(4)
    pose[:3, :3] *= 2
    bad(lambda: ramtk.ik(robot, pose, np.zeros(6)), "pose")
    pose = np.eye(4)
    pose[0, 3] = np.nan
    bad(lambda: ramtk.ik(robot, pose, np.zeros(6)), "pose")
    bad(lambda: ramtk.ik(robot, np.eye(4), [np.nan] * 6), "seed_deg")
    bad(lambda: ramtk.simulate_thermal(robot, scratch / "neg", cycles=-5), "cycles")
    bad(lambda: ramtk.scan(default_set, spheres=-1), "spheres")
    bad(lambda: ramtk.scan(default_set, radius=float("nan")), "radius")
    bad(lambda: ramtk.scan(default_set, min_depth=500, max_depth=400), "max_depth")
    bad(lambda: ramtk.scan([f.astype(np.float64) for f in left], right, cal, default_set), "left_frames[0]")
    bad(lambda: ramtk.scan(left, [np.asfortranarray(f) for f in right], cal, default_set), "right_frames[0]")
    bad(lambda: ramtk.scan(left, [np.dstack([f, f, f]) for f in right], cal, default_set), "right_frames[0]")
    bad(lambda: ramtk.scan(left, right[:-1], cal, default_set), "")  # the count: named by the C++ reader
    bad(lambda: ramtk.scan(left, right, None, default_set), "calibration")
    bad(lambda: ramtk.decode(left, "left"), "sequence")
    bad(lambda: ramtk.fit_sphere(np.zeros((10, 2))), "points")
    bad(lambda: ramtk.fit_sphere(np.zeros((300, 3)), sigma=-np.ones(300)), "sigma")
    bad(lambda: ramtk.calibrate_sensor_robot(robot, {"q1": [0.0]}), "measurements")
    bad(lambda: ramtk.robot_path("nosuchrobot"), "name")

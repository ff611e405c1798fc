#!/usr/bin/env python3
"""Worked example of docs/python.md: render a fringe set, load its frames with OpenCV, scan them
from memory, fit the sphere again from numpy, then calibrate the sensor against the robot from a
table of centres built in memory (batch forward kinematics).

    python3 scan_and_calibrate.py [--out DIR]      # from any folder, with ramtk installed

Needs only ramtk and numpy (OpenCV's cv2 when installed; the frames are read by ramtk otherwise).
Run by ctest from / in a fresh virtual environment (python.wheel_venv) and by pytest.
"""
import argparse
import pathlib
import tempfile
from typing import Any, List

import numpy as np
import numpy.typing as npt

import ramtk


def load_frames(paths: List[str]) -> List[npt.NDArray[Any]]:
    try:
        import cv2  # type: ignore[import]

        return [cv2.imread(p, cv2.IMREAD_UNCHANGED) for p in paths]
    except ImportError:
        return [ramtk.read_image(p) for p in paths]


def rotation_z_y(z_deg: float, y_deg: float) -> npt.NDArray[np.float64]:
    cz, sz = np.cos(np.radians(z_deg)), np.sin(np.radians(z_deg))
    cy, sy = np.cos(np.radians(y_deg)), np.sin(np.radians(y_deg))
    rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    r: npt.NDArray[np.float64] = rz @ ry
    return r


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--out", default="", help="scratch folder (default: a temporary one)")
    args = parser.parse_args()
    out = pathlib.Path(args.out or tempfile.mkdtemp(prefix="ramtk_example_"))
    out.mkdir(parents=True, exist_ok=True)

    # 1. A stereo fringe set of the 38.1 mm ball (simulated; a captured set has the same manifest).
    sim = ramtk.simulate_fringe(out / "set", preset="small", seed=5, force=True)
    print(f"rendered {sim.frames} images per camera, {sim.width}x{sim.height}")

    # 2. Frames in memory (e.g. straight from the cameras): scan them, reporting each stage.
    manifest = ramtk.read_manifest(sim.manifest)
    left = load_frames(manifest["resolved_images"]["left"])
    right = load_frames(manifest["resolved_images"]["right"])
    calibration = ramtk.StereoCalibration.read(str(out / "set" / manifest["calibration"]))
    stages: List[str] = []
    scan = ramtk.scan(left, right, calibration, manifest, progress=lambda stage, done, total: stages.append(stage))
    print(f"stages: {', '.join(stages)}")
    cloud = scan.cloud
    print(f"{len(cloud)} points, median sigma {np.median(cloud.sigma_mm) * 1000:.1f} um")
    ball = scan.spheres[0]
    truth = ramtk.read_truth_spheres(sim.truth)[0]
    error_um = 1000 * (ball.centre_mm - truth.centre_mm)
    sigma_um = 1000 * ball.centre_sigma_mm
    print(f"ball centre error vs truth {np.round(error_um, 2)} um (predicted sigma {np.round(sigma_um, 2)} um)")
    assert (np.abs(error_um) < 5 * sigma_um + 0.1).all(), "centre outside 5 sigma of the truth"

    # 3. The same cloud, the sphere fitted again from numpy (e.g. after your own filtering).
    near = np.linalg.norm(cloud.points_mm - ball.centre_mm, axis=1) < 30
    refit = ramtk.fit_sphere(cloud.points_mm[near], sigma=cloud.sigma_mm[near], radius=19.05)[0]
    print(f"refit on {int(near.sum())} points near the ball: radius {refit.radius_mm:.4f} mm")
    assert abs(refit.radius_mm - truth.radius_mm) < 0.05

    # 4. Sensor-to-robot calibration from a table in memory: 12 poses of a KR150, the ball on the
    #    flange seen by a sensor in front of the robot; centres with 20 um noise.
    robot = ramtk.RobotModel.read(ramtk.robot_path("kuka_kr150_r3100"))
    rng = np.random.default_rng(3)
    q_deg = np.array([0.0, -90.0, 90.0, 0.0, 0.0, 0.0]) + rng.uniform(-25, 25, size=(12, 6))
    ball_in_flange = np.array([5.0, -3.0, 180.0, 1.0])
    sensor_from_base = np.eye(4)
    sensor_from_base[:3, :3] = rotation_z_y(170.0, 15.0)
    sensor_from_base[:3, 3] = [400.0, -150.0, 2600.0]
    base_from_flange = ramtk.fk(robot, q_deg)  # 12 x 4 x 4, one C++ loop
    centres = (sensor_from_base @ base_from_flange @ ball_in_flange)[:, :3] + rng.normal(scale=0.02, size=(12, 3))
    cal = ramtk.calibrate_sensor_robot(robot, {"q_deg": q_deg, "xyz_mm": centres})
    print(cal.report)
    error = cal.ball_in_flange_mm - ball_in_flange[:3]
    print(f"ball_in_flange error {np.round(error, 4)} mm (sigma {np.round(cal.ball_std_mm, 4)} mm)")
    assert (np.abs(error) < 5 * cal.ball_std_mm + 1e-6).all()
    print("ok")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Worked example of docs/python.md: scan a fringe set, look at the cloud, fit the sphere, and feed
ball centres to the sensor-to-robot calibration.

    PYTHONPATH=build/python python3 python/examples/scan_and_calibrate.py --out /tmp/ramtk_example

Runs in ctest (python.example_scan_and_calibrate). Open3D is used to show the cloud when it is
installed and --show is given; nothing else outside numpy is needed.
"""
import argparse
import json
import os
import pathlib
import subprocess

import numpy as np

import ramtk

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="/tmp/ramtk_example", help="scratch folder")
parser.add_argument("--show", action="store_true", help="show the cloud in Open3D if installed")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

# 1. A stereo fringe set of the 38.1 mm ball (simulated here; a captured set has the same manifest).
sim = ramtk.simulate_fringe(str(out / "set"), preset="small", seed=5, force=True)
print(f"rendered {sim['frames']} images per camera, {sim['width']}x{sim['height']}")

# 2. Scan it: decode both cameras, match, triangulate, fit the sphere.
scan = ramtk.scan(sim["manifest"])
points = scan["points"]  # N x 5: x, y, z (mm, left-camera frame), sigma (mm), quality
print(f"{len(points)} points, median sigma {np.median(points[:, 3]) * 1000:.1f} um")
ball = scan["spheres"][0]
truth = ramtk.read_truth_spheres(sim["truth"])[0]
error_um = 1000 * (ball["centre_mm"] - truth["centre_mm"])
sigma_um = 1000 * np.sqrt(np.diag(ball["centre_covariance_mm2"]))
print(f"ball centre error vs truth {np.round(error_um, 2)} um (predicted sigma {np.round(sigma_um, 2)} um)")
assert (np.abs(error_um) < 5 * sigma_um + 0.1).all(), "centre outside 5 sigma of the truth"

# 3. The same cloud, the sphere fitted again from numpy (e.g. after your own filtering).
near = points[np.linalg.norm(points[:, :3] - ball["centre_mm"], axis=1) < 30]
refit = ramtk.fit_sphere(near[:, :3], sigma=near[:, 3], radius_mm=19.05)[0]
print(f"refit on {len(near)} points near the ball: radius {refit['radius_mm']:.4f} mm")
assert abs(refit["radius_mm"] - truth["radius_mm"]) < 0.05

if args.show:
    try:
        import open3d as o3d  # optional

        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points[:, :3]))
        o3d.visualization.draw_geometries([cloud])
    except ImportError:
        print("open3d is not installed; skipping the 3-D view")

# 4. Centres -> sensor-to-robot calibration. A measurement CSV (cycle,time_s,pose,q1..q6,x,y,z and
#    optionally cov_xx..cov_yz) comes from `ramtk measure`; here the simulator writes one.
robot = os.path.join(os.environ.get("RAMTK_DATASETS_DIR", "datasets"), "robots", "kuka_kr150_r3100.yaml")
binary = os.environ.get("RAMTK_BINARY", "build/tools/ramtk")
subprocess.run([binary, "simulate", "sensor-robot", "--robot", robot, "--output", str(out / "ball.csv"),
                "--truth", str(out / "truth.json"), "--poses", "12"], check=True, capture_output=True)
cal = ramtk.calibrate_sensor_robot(robot, str(out / "ball.csv"))
true_ball = np.array(json.loads((out / "truth.json").read_text())["ball_in_flange_mm"])
print(cal["report"])
print(f"ball_in_flange error {np.round(cal['ball_in_flange_mm'] - true_ball, 4)} mm "
      f"(sigma {np.round(cal['ball_std_mm'], 4)} mm)")
assert (np.abs(cal["ball_in_flange_mm"] - true_ball) < 5 * cal["ball_std_mm"] + 1e-6).all()
print("ok")

"""ramtk: robot accuracy maintenance toolkit — fringe scans, sphere centres, robot calibration,
thermal drift (docs/python.md). Millimetres and degrees at every boundary; 3-D scan results in
the left-camera frame; poses named target_from_source. Bad input raises ramtk.InputError (a
ValueError) naming the argument, or the file, line and field."""
from ._core import PARAM_NAMES, InputError, RobotModel, StereoCalibration, __version__
from ._campaign import calibrate_robot, hand_eye, measure, merge, scan_batch, simulate_campaign
from ._data import robot_path, robots
from ._diagnose import diagnose
from ._results import (BatchResult, CampaignResult, Cloud, Decoded, Diagnosis, DriftEstimate, FringeSet, HandEye,
                       IkSolution, Measurements, RobotCalibration, ScanResult, Screening, SensorRobotCalibration, Sphere,
                       ThermalSimulation, TruthSphere)
from ._robot import calibrate_sensor_robot, fk, ik, point_jacobian
from ._tables import measurement_table
from ._thermal import simulate_thermal, thermal_identify, thermal_screen
from ._vision import (decode, fit_sphere, read_image, read_manifest, read_truth_spheres, scan, scan_options,
                      simulate_fringe)

__all__ = [
    "PARAM_NAMES", "InputError", "RobotModel", "StereoCalibration", "__version__", "robot_path", "robots",
    "diagnose", "Cloud", "Decoded", "Diagnosis", "DriftEstimate", "FringeSet", "IkSolution", "ScanResult",
    "Screening", "SensorRobotCalibration", "Sphere", "ThermalSimulation", "TruthSphere", "calibrate_sensor_robot",
    "fk", "ik", "point_jacobian", "measurement_table", "simulate_thermal", "thermal_identify", "thermal_screen",
    "decode", "fit_sphere", "read_image", "read_manifest", "read_truth_spheres", "scan", "scan_options",
    "simulate_fringe", "calibrate_robot", "hand_eye", "measure", "merge", "scan_batch", "simulate_campaign",
    "BatchResult", "CampaignResult", "HandEye", "Measurements", "RobotCalibration",
]

# Laser kind of `ramtk diagnose` (issue 8): device logs and sensor-frame calibration points.
list(APPEND RAMTK_DIAGNOSE_KIND_SOURCES
  src/laser_fit.cpp src/laser_points.cpp src/laser_log.cpp src/laser_diagnose.cpp src/laser_hidden.cpp)

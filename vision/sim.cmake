# Sources of the fringe-image simulator half of ramtk::vision (camera model, stereo calibration
# files, scene, renderer, simulator). Included from vision/CMakeLists.txt.
set(RAMTK_VISION_SIM_SOURCES
  src/camera_model.cpp
  src/stereo_calibration.cpp
  src/scene.cpp
  src/fringe_renderer.cpp
  src/fringe_simulator.cpp)

# Sources of the fringe-image simulator half of ramtk::vision (scene, renderer, simulator; the camera
# model and calibration files are ramtk::camera). Included from vision/CMakeLists.txt.
set(RAMTK_VISION_SIM_SOURCES
  src/scene.cpp
  src/fringe_renderer.cpp
  src/fringe_simulator.cpp)

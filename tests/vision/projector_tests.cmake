# Camera–projector (monocular) structured light: triangulation against closed-form truth and
# finite differences, calibration files, the simulated ball through the monocular scan, and the
# real SLMaster monocular set against SLMaster's own algorithm (skipped when ../shared is absent).
ramtk_add_gtest(vision_projector_tests
  projector_triangulate_test.cpp
  scan_monocular_test.cpp
  scan_monocular_real_test.cpp
  projector_corners_test.cpp)
target_link_libraries(vision_projector_tests PRIVATE ramtk::vision ${OpenCV_LIBS})

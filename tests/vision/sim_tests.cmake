# Fringe-image simulator: camera model and calibration files against OpenCV and the real
# caliInfo.yml, ray intersections against closed forms, rendered images against analytic truth.
ramtk_add_gtest(vision_sim_tests
  sim_camera_model_test.cpp
  sim_stereo_calibration_test.cpp)
target_link_libraries(vision_sim_tests PRIVATE ramtk::vision ${OpenCV_LIBS})

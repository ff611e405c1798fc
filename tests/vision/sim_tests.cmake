# Fringe-image simulator: camera model and calibration files against OpenCV and the real
# caliInfo.yml, ray intersections against closed forms, rendered images against analytic truth,
# sensor noise against its configured statistics, seeds and written outputs.
ramtk_add_gtest(vision_sim_tests
  sim_camera_model_test.cpp
  sim_stereo_calibration_test.cpp
  sim_scene_test.cpp
  sim_renderer_test.cpp
  sim_sensor_test.cpp
  sim_simulator_test.cpp)
target_link_libraries(vision_sim_tests PRIVATE ramtk::vision ${OpenCV_LIBS} TBB::tbb nlohmann_json::nlohmann_json)

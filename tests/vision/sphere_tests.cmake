# Sphere extraction and fitting: closed forms, synthetic caps against their truth, the predicted
# centre sigma against the Monte-Carlo scatter, a ball bar, no-sphere cases, and PCL's RANSAC
# sphere fit (SACSegmentation, SACMODEL_SPHERE) on the same clouds.
find_package(PCL 1.13 REQUIRED COMPONENTS common sample_consensus segmentation)
ramtk_add_gtest(vision_sphere_tests
  sphere_fit_test.cpp
  sphere_grid_test.cpp
  sphere_crlb_test.cpp
  sphere_mc_test.cpp
  sphere_pcl_test.cpp)
target_link_libraries(vision_sphere_tests PRIVATE ramtk::vision nlohmann_json::nlohmann_json Ceres::ceres
                      pcl_common pcl_sample_consensus pcl_segmentation)
target_include_directories(vision_sphere_tests PRIVATE ${PCL_INCLUDE_DIRS})

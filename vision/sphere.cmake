# Sources of the sphere extraction and fitting half of ramtk::vision (RANSAC candidates, Ceres
# geometric fit, covariance, sphere-result JSON). Included from vision/CMakeLists.txt. Ceres is
# confined to sphere_fit_refine.cpp; no PCL is needed by the library (tests and bench compare with it).
set(RAMTK_VISION_SPHERE_SOURCES
  src/sphere_fit.cpp
  src/sphere_fit_ransac.cpp
  src/sphere_fit_refine.cpp
  src/sphere_fit_json.cpp)
set(RAMTK_VISION_SPHERE_PRIVATE_DEPS Ceres::ceres)

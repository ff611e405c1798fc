# Sources of the stereo scan half of ramtk::vision (point cloud PLY, stereo matching,
# triangulation, the scan pipeline). Included from vision/CMakeLists.txt.
set(RAMTK_VISION_SCAN_SOURCES
  src/point_cloud_ply.cpp
  src/stereo_match.cpp
  src/stereo_rectified_grid.cpp
  src/undistort_chains.cpp
  src/stereo_walk_lanes.cpp
  src/stereo_search_list.cpp
  src/back_reach_lanes.cpp
  src/triangulate.cpp
  src/scan.cpp src/scan_frames.cpp src/scan_outputs.cpp
  src/scan_roi.cpp
  src/scan_report.cpp
  src/scan_batch.cpp
  src/cloud_noise.cpp)

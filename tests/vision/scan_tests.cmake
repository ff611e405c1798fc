# Stereo scan: PLY I/O (against PCL), matching and triangulation against the simulator's truth,
# the scan pipeline and `ramtk scan` on the command line.
ramtk_add_gtest(vision_scan_tests
  scan_match_test.cpp)
target_link_libraries(vision_scan_tests PRIVATE ramtk::vision ${OpenCV_LIBS})

# Camera–projector (monocular) structured light: triangulation against closed-form truth and
# finite differences, calibration files, the simulated ball through the monocular scan, and the
# real SLMaster monocular set against SLMaster's own algorithm (skipped when ../shared is absent).
ramtk_add_gtest(vision_projector_tests
  projector_triangulate_test.cpp
  scan_monocular_test.cpp
  scan_monocular_real_test.cpp
  projector_corners_test.cpp
  tri_view_test.cpp)
target_link_libraries(vision_projector_tests PRIVATE ramtk::vision ${OpenCV_LIBS})

# `ramtk simulate fringe --monocular` then `ramtk scan` of its camera–projector set against the
# truth (the centre within a few um; its predicted sigma is ~2.3 um), and a monocular set whose
# projector calibration is missing (the file named, nothing written).
set(MONO_CLI ${CMAKE_CURRENT_BINARY_DIR}/mono_cli)
ramtk_cli_test(simulate_fringe_monocular 0
  ARGS simulate fringe --preset small --monocular --supersampling 1 --seed 2 --out ${MONO_CLI}/set --force -q
  STDOUT "simulated 2 x 19 fringe images 640x512"
  FIXTURE_SETUP vision_monocular_set)
ramtk_cli_test(scan_monocular 0
  ARGS scan ${MONO_CLI}/set/monocular.json --truth ${MONO_CLI}/set/truth/truth.json --out ${MONO_CLI}/scan --force -q
  STDOUT "scan ok: [0-9]+ points; ball_in_left_camera \\(-?0\\.00[0-9]+, -?0\\.00[0-9]+, (699\\.99|700\\.00)[0-9]+\\) mm.*error vs truth \\(ball\\)"
  FIXTURE_REQUIRED vision_monocular_set)
file(MAKE_DIRECTORY ${MONO_CLI})
file(WRITE ${MONO_CLI}/no_projector_calibration.json [=[
{"projector": {"width": 912, "height": 1140}, "direction": "vertical", "projector_calibration": "missing.yml",
 "sequence": [{"type": "phase_shift", "steps": 12, "cycles": 64}, {"type": "gray_code", "bits": 7, "complementary": true}],
 "cameras": {"left": ["set/left/00.png", "set/left/01.png", "set/left/02.png", "set/left/03.png", "set/left/04.png",
   "set/left/05.png", "set/left/06.png", "set/left/07.png", "set/left/08.png", "set/left/09.png", "set/left/10.png",
   "set/left/11.png", "set/left/12.png", "set/left/13.png", "set/left/14.png", "set/left/15.png", "set/left/16.png",
   "set/left/17.png", "set/left/18.png"]}}
]=])
ramtk_cli_test(scan_monocular_missing_calibration 1
  ARGS scan ${MONO_CLI}/no_projector_calibration.json --out ${MONO_CLI}/not_written
  STDERR "missing.yml"
  NO_PATH ${MONO_CLI}/not_written
  FIXTURE_REQUIRED vision_monocular_set)

# Tri-view: the simulated stereo set scanned stereo-only and with the projector as a third view
# (named by the manifest and by --projector-calib): the stereo pair's points kept, projector points
# added, each ball centre within 3 sigma of the truth (check_tri_view.cmake); a stereo set naming
# no projector calibration, or scanned in --roi windows, is refused with nothing written.
add_test(NAME cli.scan_tri_view
         COMMAND ${CMAKE_COMMAND} -DRAMTK=$<TARGET_FILE:ramtk> -DSET=${MONO_CLI}/set -DOUT=${MONO_CLI}/tri_view
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/check_tri_view.cmake)
set_tests_properties(cli.scan_tri_view PROPERTIES FIXTURES_REQUIRED vision_monocular_set)
ramtk_cli_test(scan_tri_view_without_projector_calibration 1
  ARGS scan ${MONO_CLI}/set/manifest.json --tri-view --out ${MONO_CLI}/tri_view_not_written
  STDERR "projector_calibration.*--projector-calib"
  NO_PATH ${MONO_CLI}/tri_view_not_written
  FIXTURE_REQUIRED vision_monocular_set)
ramtk_cli_test(scan_tri_view_with_roi_windows 1
  ARGS scan ${MONO_CLI}/set/manifest.json --tri-view --projector-calib ${MONO_CLI}/set/projector_calibration.yml
       --roi auto --out ${MONO_CLI}/tri_view_roi_not_written
  STDERR "tri_view.*roi must be full"
  NO_PATH ${MONO_CLI}/tri_view_roi_not_written
  FIXTURE_REQUIRED vision_monocular_set)

# Stereo scan: PLY I/O (against PCL), matching and triangulation against the simulator's truth,
# the scan pipeline (ball centre vs truth, no-sphere, bad calibration, the real SLMaster set; the
# rational and fisheye lens models against the pinhole case) and
# `ramtk scan` on the command line.
find_package(PCL 1.13 REQUIRED COMPONENTS common io)
ramtk_add_gtest(vision_scan_tests
  scan_ballbar_test.cpp
  scan_correlation_test.cpp
  scan_match_test.cpp
  scan_ply_test.cpp
  scan_pipeline_test.cpp
  decode_fast_test.cpp
  nonlinearity_gate_test.cpp
  stereo_walk_test.cpp
  stereo_noise_term_test.cpp
  stereo_full_search_test.cpp
  stereo_back_reach_test.cpp
  stereo_rectified_test.cpp
  stereo_walk_lanes_test.cpp
  stereo_search_list_test.cpp
  scan_shard_test.cpp
  scan_roi_test.cpp
  scan_depth_picture_test.cpp
  scan_output_formats_test.cpp
  scan_lens_models_test.cpp)
target_link_libraries(vision_scan_tests PRIVATE ramtk::vision ${OpenCV_LIBS} pcl_common pcl_io)
target_include_directories(vision_scan_tests PRIVATE ${PCL_INCLUDE_DIRS})
target_compile_definitions(vision_scan_tests PRIVATE RAMTK_TEST_OUTPUT_DIR="${CMAKE_CURRENT_BINARY_DIR}/output"
  RAMTK_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# `ramtk scan` as a user runs it: the bundled default set with its truth, and bad input that
# must fail naming the file and field with nothing written.
set(SCAN_CLI ${CMAKE_CURRENT_BINARY_DIR}/scan_cli)
file(MAKE_DIRECTORY ${SCAN_CLI})
set(SCAN_DEFAULT ${PROJECT_SOURCE_DIR}/datasets/scan_default)
ramtk_cli_test(scan_default 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --truth ${SCAN_DEFAULT}/truth/truth.json --out ${SCAN_CLI}/default --force
  STDOUT "scan ok: [0-9]+ points; ball_in_left_camera \\(-?0\\.00[0-9]+, -?0\\.00[0-9]+, 699\\.99[0-9]+\\) mm \\+- \\([0-9.]+, [0-9.]+, [0-9.]+\\) um \\(CRLB [0-9.]+, [0-9.]+, [0-9.]+ um\\).*error vs truth \\(ball\\).*CRLB [0-9.]+ um"
  # The Cramér–Rao bound beside the fit: sub-micrometre across the axis, ~1.3 um along z (the
  # library's value itself: SphereFitJson.CarriesTheResult and python/tests/test_vision.py).
  FILE ${SCAN_CLI}/default/spheres.json
  FILE_REGEX "\"crlb_centre_sigma_mm\": \\[[^0-9]*0\\.000[1-9][0-9]*,[^0-9]*0\\.000[1-9][0-9]*,[^0-9]*0\\.00[0-9]+[^0-9]*\"crlb_radius_sigma_mm\": 0\\.00[0-9]+")
# The report's sphere table carries the bound beside the fit's sigma.
ramtk_cli_test(scan_default_report 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --out ${SCAN_CLI}/report --force -q --report
  FILE ${SCAN_CLI}/report/report.html
  FILE_REGEX "Cram[^ ]*Rao bound x / y / z [^<]*</th>.*<td>0\\.4[0-9] / 0\\.4[0-9] / 1\\.[0-9][0-9]</td>")
# The fixed modulation rule (--modulation-rule fixed) on the same set: the 2 % rules' 155 649
# points (the sigma rule, the default, keeps 155 646: its threshold is 5.53 DN here).
ramtk_cli_test(scan_default_fixed_modulation 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --truth ${SCAN_DEFAULT}/truth/truth.json --modulation-rule fixed
       --out ${SCAN_CLI}/fixed_modulation --force
  STDOUT "scan ok: 155649 points; .*error vs truth \\(ball\\)")
ramtk_cli_test(scan_bad_modulation_rule 2
  ARGS scan ${SCAN_DEFAULT}/manifest.json --modulation-rule fixd --out ${SCAN_CLI}/not_written_rule
  STDERR "--modulation-rule: fixd not in")
# The sampling kernel estimated from the data (no kernel stated in the set's calibration): on
# the bundled set's small pixels the pairs' spread is about its noise and the scan keeps no kernel terms,
# which stdout and summary.json say; a bad --kernel-estimate is refused.
ramtk_cli_test(scan_default_kernel_estimate 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --kernel-estimate auto --out ${SCAN_CLI}/kernel_estimate --force -q
  STDOUT "sampling kernel: estimated variance -?0\\.0[0-9]+ \\+- 0\\.0[0-9]+ px\\^2 over [0-9]+ px \\(leverage 0\\.[0-9]\\), too little leverage"
  FILE ${SCAN_CLI}/kernel_estimate/summary.json
  FILE_REGEX "\"sampling_kernel\": {[^}]*\"pixels\": [0-9]+,[^}]*\"status\": \"too little leverage\"")
ramtk_cli_test(scan_bad_kernel_estimate 2
  ARGS scan ${SCAN_DEFAULT}/manifest.json --kernel-estimate maybe --out ${SCAN_CLI}/not_written_kernel
  STDERR "--kernel-estimate: maybe not in")
# The optional phase filter on the same set: the centre stays on the truth (its sigma is ~1.5 um).
ramtk_cli_test(scan_default_phase_filter 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --truth ${SCAN_DEFAULT}/truth/truth.json --out ${SCAN_CLI}/phase_filter --force
       --phase-filter 2
  STDOUT "scan ok: [0-9]+ points; ball_in_left_camera \\(-?0\\.00[0-9]+, -?0\\.00[0-9]+, 699\\.99[0-9]+\\) mm")
# The back pass along the distorted curves (the test hook RAMTK_TEST_HOOKS=curve_back_pass,
# tools/test_hooks.h): the same ball on the truth.
ramtk_cli_test(scan_default_curve_back_pass 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --truth ${SCAN_DEFAULT}/truth/truth.json --out ${SCAN_CLI}/curve_back_pass
       --force
  STDOUT "scan ok: [0-9]+ points; ball_in_left_camera \\(-?0\\.00[0-9]+, -?0\\.00[0-9]+, 699\\.99[0-9]+\\) mm"
  FILE ${SCAN_CLI}/curve_back_pass/summary.json FILE_REGEX "\"back_pass\": \"curve\"")
set_tests_properties(cli.scan_default_curve_back_pass PROPERTIES ENVIRONMENT RAMTK_TEST_HOOKS=curve_back_pass)
# An unknown hook name is refused, naming the variable.
ramtk_cli_test(scan_unknown_test_hook 1
  ARGS scan ${SCAN_DEFAULT}/manifest.json --out ${SCAN_CLI}/never_hook
  STDERR "RAMTK_TEST_HOOKS.*unknown hook 'curve_pass'"
  NO_PATH ${SCAN_CLI}/never_hook)
set_tests_properties(cli.scan_unknown_test_hook PROPERTIES ENVIRONMENT RAMTK_TEST_HOOKS=curve_pass)
ramtk_cli_test(scan_bad_phase_filter 2
  ARGS scan ${SCAN_DEFAULT}/manifest.json --out ${SCAN_CLI}/never_pf --phase-filter 9
  NO_PATH ${SCAN_CLI}/never_pf)
# A calibration for 1280x1024 images beside the 640x512 set.
file(READ ${SCAN_DEFAULT}/calibration.yml SCAN_CALIB)
string(REPLACE "image_size: [ 640, 512 ]" "image_size: [ 1280, 1024 ]" SCAN_CALIB_BIG "${SCAN_CALIB}")
file(WRITE ${SCAN_CLI}/wrong_size.yml "${SCAN_CALIB_BIG}")
ramtk_cli_test(scan_calibration_size_mismatch 1
  ARGS scan ${SCAN_DEFAULT}/manifest.json --calib ${SCAN_CLI}/wrong_size.yml --out ${SCAN_CLI}/not_written
  STDERR "wrong_size.yml: field 'image_size': the calibration's left camera is 1280x1024 but .*00.png is 640x512"
  NO_PATH ${SCAN_CLI}/not_written)
# R with its first element changed by 0.01: not a rotation.
string(REPLACE "data: [ 9.6152394764082316e-01, 0., 2.7472" "data: [ 9.7152394764082316e-01, 0., 2.7472"
       SCAN_CALIB_BADR "${SCAN_CALIB}")
file(WRITE ${SCAN_CLI}/bad_rotation.yml "${SCAN_CALIB_BADR}")
ramtk_cli_test(scan_calibration_not_a_rotation 1
  ARGS scan ${SCAN_DEFAULT}/manifest.json --calib ${SCAN_CLI}/bad_rotation.yml --out ${SCAN_CLI}/not_written2
  STDERR "bad_rotation.yml:[0-9]+: field 'R'.*not a rotation"
  NO_PATH ${SCAN_CLI}/not_written2)
ramtk_cli_test(scan_missing_set 1
  ARGS scan ${SCAN_CLI}/nothing_here/manifest.json --out ${SCAN_CLI}/not_written3
  STDERR "nothing_here/manifest.json"
  NO_PATH ${SCAN_CLI}/not_written3)
# Batch: the default set twice and a missing one: two rows ok, one error row, exit 1.
file(WRITE ${SCAN_CLI}/batch.txt "# sets\n${SCAN_DEFAULT}/manifest.json\n${SCAN_DEFAULT}/manifest.json\nmissing/manifest.json\n")
# x_mm within 10 um of the true 0 (FormatSignificant writes e.g. -4.85e-05 below 1e-4).
# Without -q the per-set table is printed (with -q only the totals: tests/tools/shard_merge.sh).
ramtk_cli_test(scan_batch 1
  ARGS scan --batch ${SCAN_CLI}/batch.txt --out ${SCAN_CLI}/batch --force
  STDOUT "set,status,points,x_mm.*scan_default/manifest.json,ok,[0-9]+,-?(0\\.00|[1-9]\\.[0-9]+e-0[3-9]).*missing/manifest.json,error.*scanned 3 sets: 2 ok, 0 without a sphere, 1 with errors")
# Windows around the ball: the coarse pass on the default set, and a --roi that is neither full,
# auto nor a centre.
ramtk_cli_test(scan_roi_auto 0
  ARGS scan ${SCAN_DEFAULT}/manifest.json --truth ${SCAN_DEFAULT}/truth/truth.json --roi auto --out ${SCAN_CLI}/roi --force
  STDOUT "scan ok:.*roi auto \\(coarse pass, stride 2\\): left [0-9]+,[0-9]+,[0-9]+,[0-9]+, right .*error vs truth \\(ball\\)")
ramtk_cli_test(scan_roi_bad 1
  ARGS scan ${SCAN_DEFAULT}/manifest.json --roi somewhere --out ${SCAN_CLI}/not_written_roi
  STDERR "--roi"
  NO_PATH ${SCAN_CLI}/not_written_roi)
# A batch line with a predicted centre: that set is scanned in windows around it (the default
# set's ball is at (0, 0, 700) mm); a centre that is not three numbers is refused naming the line.
file(WRITE ${SCAN_CLI}/batch_centres.txt "${SCAN_DEFAULT}/manifest.json 0.4,-0.3,701\n")
ramtk_cli_test(scan_batch_predicted_centre 0
  ARGS scan --batch ${SCAN_CLI}/batch_centres.txt --out ${SCAN_CLI}/batch_centres --force
  STDOUT "scan_default/manifest.json,ok,[0-9]+,-?(0\\.00|[1-9]\\.[0-9]+e-0[3-9]).*scanned 1 sets: 1 ok, 0 without a sphere, 0 with errors in [0-9.]+ s \\([0-9.]+ sets/s\\), peak memory [0-9]+ MB")
file(WRITE ${SCAN_CLI}/batch_bad_centre.txt "# one set\n${SCAN_DEFAULT}/manifest.json 0,700\n")
ramtk_cli_test(scan_batch_bad_centre 1
  ARGS scan --batch ${SCAN_CLI}/batch_bad_centre.txt --out ${SCAN_CLI}/batch_bad_centre -q
  STDERR "batch_bad_centre.txt:2.*predicted centre"
  NO_PATH ${SCAN_CLI}/batch_bad_centre)

# The matcher's sampling-kernel terms on a large-pixel rig (SLMaster's calibration from
# RAMTK_SHARED_DIR; skipped without it), in a target of its own.
ramtk_add_gtest(vision_kernel_scan_tests scan_kernel_test.cpp kernel_estimate_test.cpp)
target_link_libraries(vision_kernel_scan_tests PRIVATE ramtk::vision ${OpenCV_LIBS})

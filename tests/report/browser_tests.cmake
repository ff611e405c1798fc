# Reports as users open them: each command writes its report.html (fixture), then
# check_in_browser.py opens it in headless Chromium: no script or console error, every chart drawn
# by Plotly, the expected figure ids present, a screenshot saved beside it (and checked), and the
# command's PNG figures checked for size and content. Skipped (exit 77) only when Chromium is
# missing or cannot start.
find_package(Python3 COMPONENTS Interpreter)
if(NOT Python3_Interpreter_FOUND)
  message(STATUS "report browser tests: no python3, skipped")
  return()
endif()
set(REPORT_DIR ${CMAKE_CURRENT_BINARY_DIR}/reports)
set(CHECK ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/check_in_browser.py)
set(R ${RAMTK_DATASETS_DIR}/robots/kuka_kr150_r3100.yaml)
set(TH ${REPORT_DIR}/thermal)
file(WRITE ${REPORT_DIR}/batch.txt "${RAMTK_DATASETS_DIR}/scan_default/manifest.json\n${RAMTK_DATASETS_DIR}/scan_default/manifest.json\n")

# report_write(<name> FIXTURE <f> [REQUIRES <f>] COMMAND ...): a command writing a report.
function(report_write name)
  cmake_parse_arguments(W "" "FIXTURE;REQUIRES" "COMMAND" ${ARGN})
  add_test(NAME report.write_${name} COMMAND ${W_COMMAND})
  set_tests_properties(report.write_${name} PROPERTIES FIXTURES_SETUP ${W_FIXTURE})
  if(W_REQUIRES)
    set_tests_properties(report.write_${name} PROPERTIES FIXTURES_REQUIRED ${W_REQUIRES})
  endif()
endfunction()
# report_browse(<name> FIXTURE <f> ARGS ...): the browser check of a written report.
function(report_browse name)
  cmake_parse_arguments(B "" "FIXTURE" "ARGS" ${ARGN})
  add_test(NAME report.browser_${name} COMMAND ${CHECK} ${B_ARGS})
  set_tests_properties(report.browser_${name} PROPERTIES FIXTURES_REQUIRED ${B_FIXTURE} SKIP_RETURN_CODE 77
                       TIMEOUT 600)
endfunction()

report_write(scan FIXTURE report_scan COMMAND $<TARGET_FILE:ramtk> scan
  ${RAMTK_DATASETS_DIR}/scan_default/manifest.json --out ${REPORT_DIR}/scan --force -q --report)
report_browse(scan FIXTURE report_scan ARGS ${REPORT_DIR}/scan/report.html
  --expect sphere0_cloud --expect sphere0_residual --expect depth --png ${REPORT_DIR}/scan/sphere0_residual.png:1000x380)

report_write(scan_batch FIXTURE report_scan_batch COMMAND $<TARGET_FILE:ramtk> scan --batch ${REPORT_DIR}/batch.txt
  --out ${REPORT_DIR}/batch --force -q --report)
report_browse(scan_batch FIXTURE report_scan_batch ARGS ${REPORT_DIR}/batch/report.html
  --expect batch_centres --expect batch_work)

report_write(diagnose_laser FIXTURE report_diagnose_laser COMMAND $<TARGET_FILE:ramtk> diagnose
  ${RAMTK_DATASETS_DIR}/tcf/thesis_table_5_3_sensor_calibration.csv --out ${REPORT_DIR}/diagnose_5_3 --report --force)
report_browse(diagnose_laser FIXTURE report_diagnose_laser ARGS ${REPORT_DIR}/diagnose_5_3/report.html
  --expect residual_by_point --png ${REPORT_DIR}/diagnose_5_3/residual_by_point.png:1000x380)

report_write(diagnose_fringe FIXTURE report_diagnose_fringe COMMAND $<TARGET_FILE:ramtk> diagnose
  ${RAMTK_DATASETS_DIR}/scan_default/manifest.json --out ${REPORT_DIR}/diagnose_fringe --report --force)
report_browse(diagnose_fringe FIXTURE report_diagnose_fringe ARGS ${REPORT_DIR}/diagnose_fringe/report.html
  --expect residual_vs_phase --expect residual_vs_frame --expect residual_vs_level --expect image-3-residual_map
  --png ${REPORT_DIR}/diagnose_fringe/residual_vs_phase.png:1000x380)

# The real SLMaster set (../shared): the fringe diagnosis worked example of docs/diagnose_fringe.md.
if(EXISTS ${RAMTK_SHARED_DIR}/data/slmaster-binocular/caliInfo.yml)
  report_write(diagnose_slmaster FIXTURE report_diagnose_slmaster COMMAND $<TARGET_FILE:ramtk> diagnose
    ${RAMTK_DATASETS_DIR}/vision/slmaster_binocular.json --out ${REPORT_DIR}/diagnose_slmaster --report --force)
  report_browse(diagnose_slmaster FIXTURE report_diagnose_slmaster ARGS ${REPORT_DIR}/diagnose_slmaster/report.html
    --expect residual_vs_phase --expect residual_vs_level --expect image-3-residual_map
    --png ${REPORT_DIR}/diagnose_slmaster/residual_vs_level.png:1000x380)
endif()

# The thesis thermal case: simulated once, then diagnosed, screened and compensated.
report_write(simulate_thermal FIXTURE report_thermal_data COMMAND
  $<TARGET_FILE:ramtk> simulate thermal --robot ${R} --preset thesis --seed 1 --out ${TH} --force)
report_write(diagnose_robot FIXTURE report_diagnose_robot REQUIRES report_thermal_data COMMAND
  $<TARGET_FILE:ramtk> diagnose ${TH}/ball.csv --model kr150 --with ${TH}/setup.json --with ${TH}/monitoring.csv
  --with thermal=traditional --out ${REPORT_DIR}/diagnose_robot --report --force)
report_browse(diagnose_robot FIXTURE report_diagnose_robot ARGS ${REPORT_DIR}/diagnose_robot/report.html
  --expect residual_vs_time --expect heldout_before_after --expect drift_parameters
  --png ${REPORT_DIR}/diagnose_robot/drift_parameters.png:1000x420
  --png ${REPORT_DIR}/diagnose_robot/residual_vs_time.png:1000x380)
report_write(thermal_screen FIXTURE report_thermal_screen REQUIRES report_thermal_data COMMAND
  $<TARGET_FILE:ramtk> thermal screen --robot ${R} --setup ${TH}/setup.json --ball ${TH}/ball.csv
  --monitoring ${TH}/monitoring.csv --report ${REPORT_DIR}/thermal_screen.html)
report_browse(thermal_screen FIXTURE report_thermal_screen ARGS ${REPORT_DIR}/thermal_screen.html
  --expect elimination --expect selected_drift --screenshot ${REPORT_DIR}/thermal_screen.png)
report_write(thermal_compensate FIXTURE report_thermal_compensate REQUIRES report_thermal_data COMMAND
  $<TARGET_FILE:ramtk> thermal compensate --robot ${R} --setup ${TH}/setup.json --ball ${TH}/ball.csv
  --monitoring ${TH}/monitoring.csv --params d4,d6,a1,a2,a3,alpha3,alpha4,beta2 --pose-budget 6
  --report ${REPORT_DIR}/thermal_compensate.html)
report_browse(thermal_compensate FIXTURE report_thermal_compensate ARGS ${REPORT_DIR}/thermal_compensate.html
  --expect monitoring_error --expect identified_drift --screenshot ${REPORT_DIR}/thermal_compensate.png)

# The robot calibration of a simulated tracker session (calib robot --report).
set(U10 ${RAMTK_DATASETS_DIR}/robots/ur10.yaml)
report_write(simulate_robot FIXTURE report_robot_data COMMAND $<TARGET_FILE:ramtk> simulate robot-calibration
  --robot ${U10} --poses 60 --output ${REPORT_DIR}/robot_tracker.csv --truth ${REPORT_DIR}/robot_truth.yaml)
report_write(calib_robot FIXTURE report_calib_robot REQUIRES report_robot_data COMMAND $<TARGET_FILE:ramtk> calib robot
  --robot ${U10} --data ${REPORT_DIR}/robot_tracker.csv --out ${REPORT_DIR}/calib_robot --force --folds 2 --report)
report_browse(calib_robot FIXTURE report_calib_robot ARGS ${REPORT_DIR}/calib_robot/report.html
  --expect residual_per_pose --expect residual_vs_joints --expect targets_3d
  --screenshot ${REPORT_DIR}/calib_robot.png)

# The campaign's folder must not exist: removed first.
report_write(campaign FIXTURE report_campaign COMMAND sh -c
  "rm -rf '${REPORT_DIR}/campaign' && '$<TARGET_FILE:ramtk>' simulate campaign --robot '${R}' --out '${REPORT_DIR}/campaign' --cycles 3 --poses 10 -q --report")
report_browse(campaign FIXTURE report_campaign ARGS ${REPORT_DIR}/campaign/report.html
  --expect monitoring_error --png ${REPORT_DIR}/campaign/monitoring_error.png:1000x380)

# The check itself fails on a page whose charts cannot be drawn (Plotly missing): exit 1 expected.
add_test(NAME report.browser_refuses_broken_page COMMAND ${CMAKE_COMMAND}
  "-DCMD=${Python3_EXECUTABLE}|${CMAKE_CURRENT_SOURCE_DIR}/check_in_browser.py|${CMAKE_CURRENT_SOURCE_DIR}/data/broken_report.html|--expect|figure|--screenshot|${REPORT_DIR}/broken.png"
  -DEXIT=1 "-DSTDOUT_REGEX=FAIL.*(script error|Plotly)" -P ${PROJECT_SOURCE_DIR}/tests/tools/expect_run.cmake)
set_tests_properties(report.browser_refuses_broken_page PROPERTIES SKIP_REGULAR_EXPRESSION "exit code 77")

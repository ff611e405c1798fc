# Laser kind of `ramtk diagnose`: hidden-effect draws, calibration points, Table 5-3, CLI.
ramtk_add_gtest(diagnose_laser_tests laser_test.cpp laser_fit_test.cpp)
target_link_libraries(diagnose_laser_tests PRIVATE ramtk::diagnose)

set(LASER_CLI ${CMAKE_CURRENT_BINARY_DIR}/laser_cli)
file(MAKE_DIRECTORY ${LASER_CLI}/latency)
ramtk_cli_test(diagnose_laser_simulate 0
  ARGS simulate tcf --out-dir ${LASER_CLI}/latency --seed 5 --effects trigger_latency
  FIXTURE_SETUP diagnose_laser_log)
ramtk_cli_test(diagnose_laser_log 0
  ARGS diagnose ${LASER_CLI}/latency/laser_log.csv --with ${LASER_CLI}/latency/motion.json
       --model ${LASER_CLI}/latency/sensor.json --out ${LASER_CLI}/latency/diagnosis --force
  STDOUT "cause 'trigger_latency' \\(confidence 1\\): held-out RMS 0\\.[0-9]+ -> 0\\.0[1-4][0-9]* mm, (9[0-9]\\.[0-9]|100)% of the excess"
  FIXTURE_REQUIRED diagnose_laser_log)
ramtk_cli_test(diagnose_laser_log_needs_motion 1
  ARGS diagnose ${LASER_CLI}/latency/laser_log.csv --model ${LASER_CLI}/latency/sensor.json
       --out ${LASER_CLI}/latency/no_motion
  STDERR "--with"
  NO_PATH ${LASER_CLI}/latency/no_motion
  FIXTURE_REQUIRED diagnose_laser_log)
ramtk_cli_test(diagnose_laser_table_5_3 0
  ARGS diagnose ${RAMTK_DATASETS_DIR}/tcf/thesis_table_5_3_sensor_calibration.csv --out ${LASER_CLI}/table_5_3 --force
  STDOUT "cause 'beam_non_perpendicular' \\(confidence 1\\): held-out RMS 0\\.1[0-9]+ -> 0\\.01[0-9]* mm, 99\\.[0-9]% of the excess")

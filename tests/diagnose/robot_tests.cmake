# Robot/ball diagnosis: hidden-effect draws, the thesis case, building blocks; CLI runs.
ramtk_add_gtest(diagnose_robot_tests robot_test.cpp)
target_link_libraries(diagnose_robot_tests PRIVATE ramtk::diagnose)
target_compile_definitions(diagnose_robot_tests PRIVATE RAMTK_TEST_OUTPUT_DIR="${CMAKE_CURRENT_BINARY_DIR}/output")

set(_diag_thesis ${CMAKE_CURRENT_BINARY_DIR}/robot_thesis_seed1)
ramtk_cli_test(diagnose_robot_simulate_thesis 0
  ARGS simulate thermal --robot ${RAMTK_DATASETS_DIR}/robots/kuka_kr150_r3100.yaml --preset thesis --seed 1
       --out ${_diag_thesis} --force
  FIXTURE_SETUP diagnose_robot_thesis)
ramtk_cli_test(diagnose_robot_thesis_traditional 0
  ARGS diagnose ${_diag_thesis}/ball.csv --model kr150 --with ${_diag_thesis}/setup.json
       --with ${_diag_thesis}/monitoring.csv --with thermal=traditional --out ${_diag_thesis}/diagnosis --force
  STDOUT "cause 'thermal_angle_drift' \\(confidence 1\\): held-out RMS 0\\.0[45][0-9]* -> 0\\.02[0-9]* mm, (8[0-9]|9[0-9])\\.?[0-9]*% of the excess"
  FIXTURE_REQUIRED diagnose_robot_thesis)
ramtk_cli_test(diagnose_robot_bad_with 1
  ARGS diagnose ${_diag_thesis}/ball.csv --with thermal=gamma7
  STDERR "field '--with thermal'"
  FIXTURE_REQUIRED diagnose_robot_thesis)
ramtk_cli_test(diagnose_robot_monitoring_as_data 1
  ARGS diagnose ${_diag_thesis}/monitoring.csv --kind robot
  STDERR "ball measurements \\(a `pose` column\\)"
  FIXTURE_REQUIRED diagnose_robot_thesis)
ramtk_cli_test(diagnose_robot_unknown_with 1
  ARGS diagnose ${_diag_thesis}/ball.csv --with notes.txt
  STDERR "field '--with': 'notes.txt' is none of"
  FIXTURE_REQUIRED diagnose_robot_thesis)

# The help lists the causes of the tables (ramtk/diagnose/engine/*_causes.def), first and last rows.
ramtk_cli_test(diagnose_help_lists_causes 0 ARGS diagnose --help
  STDOUT "fringe:.*  projector_nonlinearity .*  signal_dependent_noise .*robot:.*  joint_offset .*  tool_offset_change .*laser:.*  beam_non_perpendicular .*  tool_axis_rotation ")

# Adding a robot cause from a test (docs/architecture.md "Where to add things"): its own process,
# the registration is process-wide.
ramtk_add_gtest(diagnose_robot_extension_tests robot_extension_test.cpp)
target_link_libraries(diagnose_robot_extension_tests PRIVATE ramtk::diagnose)

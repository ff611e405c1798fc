# Fringe diagnosis: hidden-effect draws rendered by the vision simulator (named cause and held-out
# gain against the hidden truth), parameter estimates against the simulator's truth and closed
# forms, bad input; CLI runs on a simulated set.
ramtk_add_gtest(diagnose_fringe_tests fringe_test.cpp)
target_link_libraries(diagnose_fringe_tests PRIVATE ramtk::diagnose ramtk::vision ${OpenCV_LIBS})
target_compile_definitions(diagnose_fringe_tests PRIVATE RAMTK_TEST_OUTPUT_DIR="${CMAKE_CURRENT_BINARY_DIR}/output")

set(_fringe_set ${CMAKE_CURRENT_BINARY_DIR}/cli_fringe_gamma)
ramtk_cli_test(diagnose_fringe_simulate 0 FIXTURE_SETUP diagnose_fringe_set
  ARGS simulate fringe --preset small --supersampling 2 --effect projector_nonlinearity=1.8 --seed 3 --force -q
       --out ${_fringe_set})
ramtk_cli_test(diagnose_fringe_names_gamma 0 FIXTURE_REQUIRED diagnose_fringe_set
  STDOUT "cause 'projector_nonlinearity'.*% of the excess"
  FILE ${CMAKE_CURRENT_BINARY_DIR}/cli_fringe_report/report.md
  FILE_REGEX "sampling kernel stated by the calibration: fill 1, PSF 0 px"
  ARGS diagnose ${_fringe_set}/manifest.json --out ${CMAKE_CURRENT_BINARY_DIR}/cli_fringe_report --force)
# A clean point-sampled render (one ray per pixel, sharp code edges): its calibration states fill 0,
# the diagnose takes the kernel from it and finds no effect.
set(_fringe_point ${CMAKE_CURRENT_BINARY_DIR}/cli_fringe_point)
ramtk_cli_test(diagnose_fringe_simulate_point 0 FIXTURE_SETUP diagnose_fringe_point_set
  ARGS simulate fringe --preset small --supersampling 1 --seed 21 --force -q --out ${_fringe_point})
ramtk_cli_test(diagnose_fringe_point_sampled_none 0 FIXTURE_REQUIRED diagnose_fringe_point_set
  STDOUT "fringe: no effect"
  FILE ${CMAKE_CURRENT_BINARY_DIR}/cli_fringe_point_report/report.md
  FILE_REGEX "sampling kernel stated by the calibration: fill 0, PSF 0 px"
  ARGS diagnose ${_fringe_point}/manifest.json --out ${CMAKE_CURRENT_BINARY_DIR}/cli_fringe_point_report --force)
ramtk_cli_test(diagnose_fringe_kernel_out_of_range 1 FIXTURE_REQUIRED diagnose_fringe_set STDERR "fill_factor.*\\[0, 1\\]"
  ARGS diagnose ${_fringe_set}/manifest.json --with fill_factor=2)
ramtk_cli_test(diagnose_fringe_missing_manifest 1 STDERR "does not exist"
  ARGS diagnose ${CMAKE_CURRENT_BINARY_DIR}/output/no_such_set/manifest.json)

# Adding a fringe cause from a test (docs/architecture.md "Where to add things"): its own process,
# the registration is process-wide.
ramtk_add_gtest(diagnose_fringe_extension_tests fringe_extension_test.cpp)
target_link_libraries(diagnose_fringe_extension_tests PRIVATE ramtk::diagnose ramtk::vision ${OpenCV_LIBS})

# The camera's sampling kernel: sets written from the physics alone (kernel_physics_generator.h).
ramtk_add_gtest(diagnose_fringe_kernel_tests fringe_kernel_test.cpp)
target_link_libraries(diagnose_fringe_kernel_tests PRIVATE ramtk::diagnose ramtk::vision ${OpenCV_LIBS})

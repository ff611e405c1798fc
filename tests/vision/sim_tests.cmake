# Fringe-image simulator (the camera model and calibration files are tested in tests/camera): ray intersections against closed forms, rendered images against analytic truth,
# sensor noise against its configured statistics, seeds and written outputs.
ramtk_add_gtest(vision_sim_tests
  sim_scene_test.cpp
  sim_renderer_test.cpp
  sim_sensor_test.cpp
  sim_simulator_test.cpp
  sim_kernel_test.cpp)
target_link_libraries(vision_sim_tests PRIVATE ramtk::vision ${OpenCV_LIBS} TBB::tbb nlohmann_json::nlohmann_json)

# `ramtk simulate fringe` run as a user would (the expect_run.cmake script of tests/tools).

set(SIM_OUT ${CMAKE_CURRENT_BINARY_DIR}/cli_sim_out)
ramtk_cli_test(simulate_fringe_small 0
  ARGS simulate fringe --preset small --out ${SIM_OUT} --seed 5 --supersampling 1 --effect defocus=1.5
       --effect projector_nonlinearity=2.2 --force -q
  STDOUT "simulated 2 x 19 fringe images 640x512 in .*cli_sim_out")
ramtk_cli_test(simulate_fringe_unknown_effect 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --effect gamma=2.2
  STDERR "field '--effect': unknown effect 'gamma'")
ramtk_cli_test(simulate_fringe_bad_magnitude 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --effect defocus=wide
  STDERR "field '--effect defocus': expected a number, got 'wide'")
ramtk_cli_test(simulate_fringe_negative_magnitude 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --effect defocus=-2
  STDERR "effect defocus: magnitude \\(blur sigma, px\\) must be in")
ramtk_cli_test(simulate_fringe_unknown_preset 1
  ARGS simulate fringe --preset huge --out ${SIM_OUT}_bad
  STDERR "field '--preset': unknown preset 'huge'")
ramtk_cli_test(simulate_fringe_missing_out 2 ARGS simulate fringe --preset small STDERR "--out is required")
ramtk_cli_test(simulate_fringe_bad_sphere 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --sphere 1,2,700
  STDERR "field '--sphere': expected 4 comma-separated values, got 3")
ramtk_cli_test(simulate_fringe_bad_direction 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --direction diagonal
  STDERR "field '--direction': expected vertical or horizontal")
ramtk_cli_test(simulate_fringe_bad_sequence 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --sequence ps:4
  STDERR "field '--sequence': sequence block 'ps:4' lacks CYCLES \\(expected ps:STEPS:CYCLES")
# An unknown block is refused listing the codec table's forms.
ramtk_cli_test(simulate_fringe_unknown_sequence_block 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --sequence ps:12:64,zz:3
  STDERR "field '--sequence': unknown sequence block 'zz:3': the codec table has ps:STEPS:CYCLES.*gc:BITS, cgc:BITS, het:STEPS:CYCLES1/CYCLES2")
ramtk_cli_test(simulate_fringe_bmp_needs_8_bit 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --frame-format bmp --bits 12
  STDERR "field 'frame_format': bmp holds 8-bit frames")
ramtk_cli_test(simulate_fringe_heterodyne 0
  ARGS simulate fringe --out ${SIM_OUT}_het --force -q --supersampling 1 --sequence het:4:70/64/59
  STDOUT "simulated 2 x 12 fringe images 640x512")
# The written calibration states the sampling kernel the render used (sampling_kernel1/2).
ramtk_cli_test(simulate_fringe_states_kernel 0
  ARGS simulate fringe --preset small --out ${SIM_OUT}_kernel --supersampling 2 --fill-factor 0.5 --psf-sigma 0.25
       --sequence ps:3:16,cgc:5 --force -q
  FILE ${SIM_OUT}_kernel/calibration.yml
  FILE_REGEX "sampling_kernel2:[^a-z]*fill_factor: 5[.]0+e-01[^a-z]*psf_sigma_px: 2[.]50+e-01")
ramtk_cli_test(simulate_fringe_kernel_needs_rays 1
  ARGS simulate fringe --out ${SIM_OUT}_bad --supersampling 1 --fill-factor 1
  STDERR "field 'supersampling': 1 ray per pixel samples a point")

# Hidden draws from the independent generators (tests/independent: ramtk_indep_gen, written from the
# physics with no code shared with diagnose; issue 15), diagnosed by `ramtk diagnose` and scored
# against each set's truth.json by check_independent.cmake. Included at the end of tests/ (deferred
# from tests/diagnose/CMakeLists.txt) so that the generator's target exists when it is built.
if(NOT TARGET ramtk_indep_gen OR NOT TARGET ramtk)
  return()
endif()
set(_indep_check ${CMAKE_CURRENT_LIST_DIR}/check_independent.cmake)
set(_indep_work ${CMAKE_BINARY_DIR}/tests/diagnose/independent)
# kind effect seed [gain]: clean sets (fringe photon noise at camera gains 1, 4, 16), catalogued
# effects (fringe: the knee and camera vs projector blur; seed 2 of camera_defocus is read as the
# projector's blur, docs/diagnose_fringe.md), and out-of-catalogue ones (robot eccentric encoder: joint_cyclic_error or unexplained
# with its joint angle; laser speed ripple: unexplained with the angle along the circle).
set(_indep_draws
  "fringe none 1 1" "fringe none 2 4" "fringe none 3 16"
  "fringe soft_knee_response 1" "fringe camera_defocus 1" "fringe defocus 1"
  "robot none 1"
  "robot joint_compliance 1" "robot joint_compliance 2" "robot joint_compliance 3"
  "robot joint_cyclic_error 1" "robot joint_cyclic_error 3" "robot joint_cyclic_error 5"
  "robot link_length_error 1" "robot link_length_error 3"
  "robot thermal_length_drift 1"
  "robot joint_offset 1"
  "laser none 1" "laser none 2"
  "laser beam_non_perpendicular 1" "laser beam_non_perpendicular 2"
  "laser speed_ripple 1" "laser speed_ripple 3")
foreach(_draw IN LISTS _indep_draws)
  string(REPLACE " " ";" _d "${_draw}")
  list(GET _d 0 _kind)
  list(GET _d 1 _effect)
  list(GET _d 2 _seed)
  set(_name diagnose.independent.${_kind}_${_effect}_${_seed})
  set(_gain_arg)
  list(LENGTH _d _n)
  if(_n GREATER 3)
    list(GET _d 3 _gain)
    set(_gain_arg -DGAIN=${_gain})
    set(_name ${_name}_gain${_gain})
  endif()
  add_test(NAME ${_name}
           COMMAND ${CMAKE_COMMAND} -DGEN=$<TARGET_FILE:ramtk_indep_gen> -DRAMTK=$<TARGET_FILE:ramtk>
                   -DKIND=${_kind} -DEFFECT=${_effect} -DSEED=${_seed} ${_gain_arg}
                   -DWORK=${_indep_work}/${_kind}_${_effect}_${_seed} -P ${_indep_check})
  set_tests_properties(${_name} PROPERTIES LABELS "diagnose;independent")
endforeach()

# Tri-view on the simulated stereo set (`ramtk scan --tri-view`): scans the set stereo-only and
# with the projector as a third view, its calibration named by the manifest (a copy of the set's
# manifest.json with projector_calibration added) and by --projector-calib, then checks
#  * the tri-view scans keep the stereo pair's points (the same count as the stereo-only scan) and
#    add projector points: points >= the stereo-only points, projector_points > 0;
#  * each scan's ball centre within 3 times its predicted sigma of the simulator's truth (the
#    error's norm against the norm of the per-axis sigmas).
#   cmake -DRAMTK=path/to/ramtk -DSET=set_folder -DOUT=folder -P check_tri_view.cmake
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
file(READ "${SET}/manifest.json" manifest)
string(JSON manifest SET "${manifest}" projector_calibration "\"projector_calibration.yml\"")
file(WRITE "${SET}/tri_view.json" "${manifest}")

# Runs `ramtk scan` into OUT/<name>; sets <name>_points, <name>_json (summary.json) and checks the centre.
function(run_scan name)
  execute_process(COMMAND "${RAMTK}" scan ${ARGN} --truth "${SET}/truth/truth.json" --out "${OUT}/${name}" -q
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: exit ${rc}\n${out}\n${err}")
  endif()
  message(STATUS "${name}: ${out}")
  if(NOT out MATCHES "\\|e\\| ([0-9.]+) um \\(predicted sigma ([0-9.]+) um")
    message(FATAL_ERROR "${name}: no error against the truth in\n${out}")
  endif()
  set(e ${CMAKE_MATCH_1})
  set(s ${CMAKE_MATCH_2})
  file(READ "${OUT}/${name}/summary.json" json)
  string(JSON points GET "${json}" points)
  set(${name}_points ${points} PARENT_SCOPE)
  set(${name}_json "${json}" PARENT_SCOPE)
  set(${name}_e ${e} PARENT_SCOPE)
  set(${name}_s ${s} PARENT_SCOPE)
endfunction()

# a <= 3 b for decimals a, b (in micrometres, at most 3 decimals): compared in nanometres.
function(check_within name a b)
  foreach(v a b)
    string(REGEX MATCH "^([0-9]+)(\\.([0-9]*))?$" m "${${v}}")
    string(SUBSTRING "${CMAKE_MATCH_3}000" 0 3 frac)
    math(EXPR ${v}_nm "${CMAKE_MATCH_1} * 1000 + 1${frac} - 1000")
  endforeach()
  math(EXPR limit "3 * ${b_nm}")
  if(a_nm GREATER limit)
    message(FATAL_ERROR "${name}: centre error ${a} um is more than 3 x the predicted sigma ${b} um")
  endif()
endfunction()

run_scan(stereo "${SET}/manifest.json")
run_scan(manifest "${SET}/tri_view.json" --tri-view)
run_scan(option "${SET}/manifest.json" --tri-view --projector-calib "${SET}/projector_calibration.yml")
foreach(name stereo manifest option)
  check_within(${name} ${${name}_e} ${${name}_s})
endforeach()
foreach(name manifest option)
  string(JSON stereo_part GET "${${name}_json}" tri_view stereo_points)
  string(JSON projector_part GET "${${name}_json}" tri_view projector_points)
  if(NOT stereo_part EQUAL stereo_points)
    message(FATAL_ERROR "${name}: ${stereo_part} stereo points, the stereo-only scan ${stereo_points}")
  endif()
  if(NOT projector_part GREATER 0 OR ${name}_points LESS stereo_points)
    message(FATAL_ERROR "${name}: ${${name}_points} points (${projector_part} projector), stereo-only ${stereo_points}")
  endif()
  math(EXPR sum "${stereo_part} + ${projector_part}")
  if(NOT sum EQUAL ${name}_points)
    message(FATAL_ERROR "${name}: ${stereo_part} + ${projector_part} != ${${name}_points} points")
  endif()
endforeach()
string(JSON has_tri_view ERROR_VARIABLE none GET "${stereo_json}" tri_view)
if(none STREQUAL "NOTFOUND")
  message(FATAL_ERROR "the stereo-only summary.json has a tri_view block")
endif()
message(STATUS "ok: stereo ${stereo_points} points; tri-view ${manifest_points} (manifest), ${option_points} (--projector-calib)")

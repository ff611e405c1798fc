# ramtk_library_sources(ROOT OUT): the library modules' C++ sources and headers under ROOT (the
# modules of docs/architecture.md and tools/), without tests, build trees, third_party and the
# .def tables.
function(ramtk_library_sources root out)
  set(globs "")
  foreach(module calib camera campaign core diagnose image kinematics report tcf thermal vision tools)
    list(APPEND globs ${root}/${module}/*.cpp ${root}/${module}/*.h)
  endforeach()
  file(GLOB_RECURSE found ${globs})
  set(kept "")
  foreach(source IN LISTS found)
    file(RELATIVE_PATH relative ${root} ${source})
    if(NOT relative MATCHES "(^|/)(build[^/]*|tests|third_party|_deps)/")
      list(APPEND kept ${source})
    endif()
  endforeach()
  list(SORT kept)
  set(${out} ${kept} PARENT_SCOPE)
endfunction()

# ramtk_add_module(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates the library target ramtk_<name> with the alias ramtk::<name>, public headers in
# <name>/include (installed as ramtk/<name>/...), warnings from ramtk_compile_options, and
# registers it for installation and the exported package config.
function(ramtk_add_module name)
  cmake_parse_arguments(M "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target ramtk_${name})
  add_library(${target} ${M_SOURCES})
  add_library(ramtk::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ramtk_${name})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_link_libraries(${target} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS})
  ramtk_target_defaults(${target})
  set_property(GLOBAL APPEND PROPERTY RAMTK_MODULE_TARGETS ${target})
  set_property(GLOBAL APPEND PROPERTY RAMTK_MODULE_INCLUDE_DIRS ${CMAKE_CURRENT_SOURCE_DIR}/include/ramtk)
endfunction()

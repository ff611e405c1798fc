# Robot/ball measurements kind of `ramtk diagnose` (diagnose/include/ramtk/diagnose/robot.h).
include(GNUInstallDirs)
set(_robot_sources src/robot_linear.cpp src/robot_rows.cpp src/robot_candidates.cpp src/robot_multicause.cpp src/robot_diagnose.cpp
                   src/robot_plots.cpp src/robot_hidden.cpp src/robot_identify.cpp)
list(APPEND RAMTK_DIAGNOSE_KIND_SOURCES ${_robot_sources})
# Bundled robot names (--model kr150) are looked up in the source tree, then the install prefix.
set_source_files_properties(src/robot_rows.cpp PROPERTIES COMPILE_DEFINITIONS
  "RAMTK_DIAGNOSE_ROBOTS_DIR=\"${PROJECT_SOURCE_DIR}/datasets/robots\";RAMTK_DIAGNOSE_INSTALLED_ROBOTS_DIR=\"${CMAKE_INSTALL_FULL_DATADIR}/ramtk/robots\"")

# Install rules and a package config so another CMake project can find_package(ramtk).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(RAMTK_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/ramtk)
get_property(RAMTK_MODULE_TARGETS GLOBAL PROPERTY RAMTK_MODULE_TARGETS)
get_property(RAMTK_MODULE_INCLUDE_DIRS GLOBAL PROPERTY RAMTK_MODULE_INCLUDE_DIRS)
install(TARGETS ${RAMTK_MODULE_TARGETS} ramtk_compile_options
        EXPORT ramtkTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS ramtk RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${RAMTK_MODULE_INCLUDE_DIRS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY datasets/robots DESTINATION ${CMAKE_INSTALL_DATADIR}/ramtk)
install(EXPORT ramtkTargets NAMESPACE ramtk:: DESTINATION ${RAMTK_INSTALL_CMAKEDIR})

configure_package_config_file(cmake/ramtkConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/ramtkConfig.cmake
  INSTALL_DESTINATION ${RAMTK_INSTALL_CMAKEDIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ramtkConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ramtkConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/ramtkConfigVersion.cmake
        DESTINATION ${RAMTK_INSTALL_CMAKEDIR})

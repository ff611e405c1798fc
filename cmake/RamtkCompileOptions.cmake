# Warnings and sanitizers for ramtk's own targets (applied through ramtk_target_defaults()).
add_library(ramtk_compile_options INTERFACE)
target_compile_options(ramtk_compile_options INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor>)
if(RAMTK_WERROR)
  target_compile_options(ramtk_compile_options INTERFACE -Werror)
endif()
if(RAMTK_SANITIZE)
  target_compile_options(ramtk_compile_options INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(ramtk_compile_options INTERFACE -fsanitize=address,undefined)
endif()

# ccache, when present, keeps CI re-builds on the same machine short.
find_program(RAMTK_CCACHE ccache)
if(RAMTK_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_C_COMPILER_LAUNCHER ${RAMTK_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${RAMTK_CCACHE})
endif()

# Private (build-only) defaults for a ramtk target.
function(ramtk_target_defaults target)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:ramtk_compile_options>)
endfunction()

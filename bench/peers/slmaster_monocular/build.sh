#!/bin/sh
# Build SLMaster's CPU structured-light sources (commit d1a0fe4) + the monocular driver.
# Everything stays under /tmp/peer-slm-mono.
set -e
ROOT=${PEER_DIR:-${TMPDIR:-/tmp}/peer-slm-mono}
REPO=${1:?usage: build.sh GIT_DIR   (the git directory that fetch printed for github:Practice3DVision/SLMaster)}
mkdir -p "$ROOT"; cp "$(dirname "$0")/driver.cpp" "$ROOT"/; cd "$ROOT"
# Sources: the cpuStructuredLight target (src/algorithm/CMakeLists.txt globs
# cpuStructuredLight/*.cpp) plus its depth-map-to-cloud tool (src/cameras/tool.cpp).
# (git show per file: the mirror lacks some large data blobs, and git archive
#  stops on them, silently dropping files.)
for f in $(git -C "$REPO" ls-tree -r --name-only HEAD src/algorithm/cpuStructuredLight) \
         src/algorithm/algorithm.h src/common.h src/cameras/tool.h src/cameras/tool.cpp \
         src/cameras/caliInfo.h src/cameras/caliInfo.cpp; do
  [ -f "$f" ] || { mkdir -p "$(dirname "$f")"; git -C "$REPO" show "HEAD:$f" > "$f"; }
done
# SLMaster's CPU static target has no compile definitions (BUILD_SHARED_LIBS /
# DLL_EXPORTS only for the shared build); its Release flags are MSVC's /O2.
CXX=${CXX:-g++}
CXXFLAGS="-O3 -march=native -std=c++17 -DNDEBUG"
INC="-Isrc -Isrc/cameras -Isrc/algorithm -I/usr/include/eigen3 -I/usr/include/pcl-1.13 $(pkg-config --cflags opencv4)"
mkdir -p obj
OBJS=""
for f in src/algorithm/cpuStructuredLight/*.cpp src/cameras/tool.cpp src/cameras/caliInfo.cpp; do
  o=obj/$(basename "$f" .cpp).o
  $CXX $CXXFLAGS $INC -c "$f" -o "$o"
  OBJS="$OBJS $o"
done
ar rcs obj/libslm_cpu.a $OBJS
$CXX $CXXFLAGS $INC driver.cpp obj/libslm_cpu.a -o driver \
  $(pkg-config --libs opencv4) -lpcl_common -lpthread
echo "built $ROOT/driver"

#!/usr/bin/env bash
# Sets up a Debian 12 machine for ramtk and builds it in Release. Idempotent: packages already
# present are not reinstalled, and the build is incremental (ccache keeps objects between runs).
#
#   bash scripts/setup.sh            # install what is missing, configure, build into ./build
#   RAMTK_BUILD_DIR=/tmp/b bash scripts/setup.sh
#   RAMTK_SKIP_INSTALL=1 bash scripts/setup.sh   # build only
set -euo pipefail
cd "$(dirname "$0")/.."

# The exact Debian 12 (bookworm) packages ramtk needs: the one place they are listed.
PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev            # linear algebra
  libyaml-cpp-dev          # robot model files
  nlohmann-json3-dev       # manifests and results
  libcli11-dev             # the ramtk command line
  libtbb-dev               # parallel loops
  libxxhash-dev            # XXH3-128 of input files in every output's provenance (header-only use)
  xxhash                   # xxhsum: the peer the provenance hash is tested against
  libopencv-dev libopencv-contrib-dev  # calibration, image ops, structured_light peer
  libopenimageio-dev       # image and EXR I/O
  libpng-dev libdeflate-dev  # PNG frames: libpng, and one-call inflate of grey camera frames
  openimageio-tools        # OpenImageIO's CMake config references its tools (iconvert, ...)
  libceres-dev             # non-linear least squares
  libboost-dev             # header-only: statistical distributions (diagnose)
  libpcl-dev               # clouds, RANSAC, search (pulls VTK)
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev         # bench/
  liborocos-kdl-dev        # peer kinematics library for tests and benchmarks
  python3                  # bench/diagnose_independent_sweep.py and its ctest smoke run
  pybind11-dev python3-dev # the Python module (import ramtk, docs/python.md)
  python3-numpy python3-pytest  # its arrays and its tests
  python3-venv python3-pip python3-setuptools python3-wheel  # the wheel (pyproject.toml) and its venv test
  mypy python3-opencv      # stubs checked (mypy --strict, stubtest); cv2-loaded frames in tests and examples
  parallel                 # GNU parallel: the sharded-batch one-liner of docs/cluster.md and its ctest
  slurm-wlm munge          # a single-node Slurm for the job-array recipe of docs/cluster.md (ctest -L slurm)
  libspdlog-dev            # logging (core/log.h): levels, timestamps, the --log-file sink
  opencv-doc               # its real stereo chessboard images: ctest RealBoard.* (calib on real boards)
  gnuplot-nox              # PNG figures (report/gnuplot.h)
  python3-plotly uglifyjs  # Plotly.js, minified at build time and inlined into HTML reports
  chromium                 # the browser test of the HTML reports (ctest report.browser_*)
)

log() { printf '[setup] %s\n' "$*"; }

if [ -r /etc/os-release ]; then
  . /etc/os-release
  if [ "${ID:-}" != "debian" ] || [ "${VERSION_ID:-}" != "12" ]; then
    log "warning: this script targets Debian 12; this is ${PRETTY_NAME:-unknown}"
  fi
fi

if [ "${RAMTK_SKIP_INSTALL:-0}" != "1" ]; then
  missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""
    if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
    log "installing ${#missing[@]} missing packages: ${missing[*]}"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
  else
    log "all ${#PACKAGES[@]} packages present"
  fi
fi

BUILD_DIR="${RAMTK_BUILD_DIR:-build}"
JOBS="${RAMTK_JOBS:-$(nproc)}"
log "configuring ${BUILD_DIR} (Release)"
cmake -S . -B "${BUILD_DIR}" -G Ninja -DCMAKE_BUILD_TYPE=Release ${RAMTK_CMAKE_ARGS:-} >/dev/null
log "building with ${JOBS} jobs"
cmake --build "${BUILD_DIR}" -j "${JOBS}"
# `import ramtk` from Debian's python3 without setting PYTHONPATH: a .pth file naming the build's
# python/ folder in the interpreter's site-packages (docs/python.md).
if [ -d "${BUILD_DIR}/python" ] && [ -x /usr/bin/python3 ]; then
  site=$(/usr/bin/python3 -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  SUDO=""
  if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
  if $SUDO mkdir -p "${site}" && echo "$(cd "${BUILD_DIR}/python" && pwd)" | $SUDO tee "${site}/ramtk-build.pth" >/dev/null; then
    log "python: import ramtk works from /usr/bin/python3 (${site}/ramtk-build.pth)"
  else
    log "python: could not write ${site}/ramtk-build.pth; use PYTHONPATH=${BUILD_DIR}/python"
  fi
fi
log "done: ${BUILD_DIR}/tools/ramtk"

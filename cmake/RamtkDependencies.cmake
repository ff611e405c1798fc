# Every third-party library ramtk uses, found once here. Packages come from Debian 12
# (scripts/setup.sh installs exactly these).
set(THREADS_PREFER_PTHREAD_FLAG ON)
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
# spdlog: the logging behind core/log.h (levels, time stamps, the --log-file sink).
find_package(spdlog REQUIRED)
find_package(TBB REQUIRED)
# xxHash (header only, XXH_INLINE_ALL): the XXH3-128 of input files in every output's provenance.
find_path(RAMTK_XXHASH_INCLUDE_DIR xxhash.h REQUIRED)
find_package(OpenCV 4.6 REQUIRED COMPONENTS core imgproc imgcodecs calib3d features2d
             structured_light phase_unwrapping aruco)
find_package(OpenImageIO REQUIRED)
find_package(Ceres 2.1 REQUIRED)
# Boost (headers only): statistical distributions in diagnose/.
find_package(Boost 1.74 REQUIRED)
# PCL pulls VTK; only the components ramtk uses are requested.
find_package(PCL 1.13 REQUIRED COMPONENTS common io search kdtree sample_consensus)
if(RAMTK_BUILD_TESTS)
  find_package(GTest REQUIRED)
  # Orocos KDL is the peer library the kinematics tests and benchmarks compare against.
  find_package(orocos_kdl REQUIRED)
endif()
if(RAMTK_BUILD_BENCH)
  find_package(benchmark REQUIRED)
  find_package(orocos_kdl REQUIRED)
endif()
message(STATUS "ramtk deps: Eigen ${Eigen3_VERSION}, OpenCV ${OpenCV_VERSION}, Ceres ${Ceres_VERSION}, "
               "PCL ${PCL_VERSION}, OpenImageIO ${OpenImageIO_VERSION}, TBB ${TBB_VERSION}")

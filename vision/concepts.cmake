# vision's concept libraries and what each may use (docs/architecture.md, "vision's concept
# libraries"). vision/CMakeLists.txt links each library to exactly these, so an include of any
# other library's header does not compile; vision/check_layering.cmake (the test
# vision.layering) checks every include of vision/ and of the tests against the same table.
# Read by the build and by `cmake -P`, so plain set() only.
set(RAMTK_VISION_CONCEPTS kernels fringe decode stereo projector sphere sim scan)
# Concept libraries each one may include (besides itself).
set(RAMTK_VISION_USES_kernels "")
set(RAMTK_VISION_USES_fringe kernels)
set(RAMTK_VISION_USES_decode fringe kernels)
set(RAMTK_VISION_USES_stereo decode fringe kernels)
set(RAMTK_VISION_USES_projector stereo decode fringe kernels)
set(RAMTK_VISION_USES_sphere kernels)
set(RAMTK_VISION_USES_sim fringe kernels)
set(RAMTK_VISION_USES_scan stereo projector sphere sim decode fringe kernels)
# ramtk modules outside vision each one may include.
set(RAMTK_VISION_MODULES_kernels core camera)
set(RAMTK_VISION_MODULES_fringe core image camera)
set(RAMTK_VISION_MODULES_decode core image camera)
set(RAMTK_VISION_MODULES_stereo core image camera)
set(RAMTK_VISION_MODULES_projector core image camera)
set(RAMTK_VISION_MODULES_sphere core camera)
set(RAMTK_VISION_MODULES_sim core image camera)
set(RAMTK_VISION_MODULES_scan core image camera report)

# `ramtk manifest` and manifests with globs (included from CMakeLists.txt).
ramtk_add_gtest(manifest_tests manifest_builder_test.cpp sequence_spec_test.cpp)
target_link_libraries(manifest_tests PRIVATE ramtk::vision)
add_test(NAME cli.manifest_slmaster
         COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/manifest_slmaster.sh $<TARGET_FILE:ramtk> ${RAMTK_SHARED_DIR}
                 ${RAMTK_DATASETS_DIR}/vision/slmaster_binocular.json ${CMAKE_CURRENT_BINARY_DIR}/manifest_slmaster)
set_tests_properties(cli.manifest_slmaster PROPERTIES SKIP_RETURN_CODE 77)
# `ramtk manifest` reads the sequence with the same parser: an unknown block names the table.
ramtk_cli_test(manifest_unknown_sequence_block 1
  ARGS manifest ${CMAKE_CURRENT_BINARY_DIR} --sequence ps:12:64,cgc:7,zz:3 --projector 1280x720
       --out ${CMAKE_CURRENT_BINARY_DIR}/manifest_unknown_block.json
  STDERR "field '--sequence': unknown sequence block 'zz:3': the codec table has ps:STEPS:CYCLES"
  NO_PATH ${CMAKE_CURRENT_BINARY_DIR}/manifest_unknown_block.json)

# `ramtk manifest` and manifests with globs (included from CMakeLists.txt).
ramtk_add_gtest(manifest_tests manifest_builder_test.cpp sequence_spec_test.cpp)
target_link_libraries(manifest_tests PRIVATE ramtk::vision)
add_test(NAME cli.manifest_slmaster
         COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/manifest_slmaster.sh $<TARGET_FILE:ramtk> ${RAMTK_SHARED_DIR}
                 ${RAMTK_DATASETS_DIR}/vision/slmaster_binocular.json ${CMAKE_CURRENT_BINARY_DIR}/manifest_slmaster)
set_tests_properties(cli.manifest_slmaster PROPERTIES SKIP_RETURN_CODE 77)

# Procedural sample volumes, generated at build time.
# vbl_sample_cloud (ALL): ${PROJECT_BINARY_DIR}/samples/cloud.vdb, the demo/benchmark cloud (make_cloud.cc).
# VBL_GENERATORS_FROM: reuse that build folder's generator (see tests/fixtures/CMakeLists.txt).
if(VBL_GENERATORS_FROM)
  add_executable(vbl_make_cloud IMPORTED)
  set_target_properties(vbl_make_cloud PROPERTIES IMPORTED_LOCATION ${VBL_GENERATORS_FROM}/samples/vbl_make_cloud)
else()
  add_executable(vbl_make_cloud ${CMAKE_CURRENT_LIST_DIR}/make_cloud.cc)
  target_link_libraries(vbl_make_cloud PRIVATE vbl::openvdb)
endif()
set(VBL_SAMPLE_CLOUD ${PROJECT_BINARY_DIR}/samples/cloud.vdb)
add_custom_command(OUTPUT ${VBL_SAMPLE_CLOUD}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/samples
  COMMAND vbl_make_cloud ${VBL_SAMPLE_CLOUD}
  DEPENDS vbl_make_cloud
  COMMENT "Generating the sample cloud ${VBL_SAMPLE_CLOUD}"
  VERBATIM)
add_custom_target(vbl_sample_cloud ALL DEPENDS ${VBL_SAMPLE_CLOUD})

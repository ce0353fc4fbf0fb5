# Issue 13 item 4: the artifact-free vbl against pt and vrl at equal CPU time (bench/bench_vbl_artifacts.c).
# Run: build/bench/bench_vbl_artifacts --res 48x36 --cpu 20 --reference-seconds 60
add_executable(bench_vbl_artifacts ${CMAKE_CURRENT_LIST_DIR}/bench_vbl_artifacts.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_vbl_artifacts PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_vbl_artifacts PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_vbl_artifacts PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_vbl_artifacts PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_vbl_artifacts vbl_sample_cloud)
endif()

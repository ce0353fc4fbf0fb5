# Issue-3 benchmark: pt / vpl / vrl at equal wall-clock time on the sample cloud against a cached
# long pt reference (bench/bench_methods.c). Run: build/bench/bench_methods [--reference-seconds S]
# (defaults: samples/cloud.json with build/samples/cloud.vdb, 96x72, budgets 2,5,10,20 s).
add_executable(bench_methods ${CMAKE_CURRENT_LIST_DIR}/bench_methods.c)
set_target_properties(bench_methods PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_methods PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_methods PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_methods PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_DEFAULT_SCENE="${PROJECT_SOURCE_DIR}/samples/cloud.json"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_methods vbl_sample_cloud)
endif()

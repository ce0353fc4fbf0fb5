# Issue-14 benchmark: pt's switches on/off per layer at equal samples and equal time (bench/bench_pt.c).
# Run: build/bench/bench_pt --configs eq_off,eq_on --spp 64 --res 64x48
add_executable(bench_pt ${CMAKE_CURRENT_LIST_DIR}/bench_pt.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_pt PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_pt PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_pt PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_pt PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_pt vbl_sample_cloud)
endif()

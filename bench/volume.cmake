# Volume benchmarks: density lookups (PNanoVDB vs OpenVDB) and transmittance estimators on the
# procedural cloud. Run: build/bench/bench_volume [FILE.vdb] (default build/samples/cloud.vdb).
add_executable(bench_volume ${CMAKE_CURRENT_LIST_DIR}/bench_volume.c ${CMAKE_CURRENT_LIST_DIR}/bench_volume_openvdb.cc)
set_target_properties(bench_volume PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_volume PRIVATE vbl_static vbl::openvdb OpenMP::OpenMP_C OpenMP::OpenMP_CXX m)
target_include_directories(bench_volume PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_include_directories(bench_volume SYSTEM PRIVATE ${VBL_NANOVDB_INCLUDE_DIR})
target_compile_definitions(bench_volume PRIVATE VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb")

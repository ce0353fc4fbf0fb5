# Peak memory of loading a large grid (issue 18): bench_load_memory.sh [EDGE] generates a ball of
# EDGE^3-ish voxels with make_big_grid and loads its .vdb and .nvdb with bench_load_volume.
add_executable(bench_make_big_grid ${CMAKE_CURRENT_LIST_DIR}/make_big_grid.cc)
set_target_properties(bench_make_big_grid PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_make_big_grid PRIVATE vbl::openvdb)
target_include_directories(bench_make_big_grid SYSTEM PRIVATE ${VBL_NANOVDB_INCLUDE_DIR})
add_executable(bench_load_volume ${CMAKE_CURRENT_LIST_DIR}/bench_load_volume.c)
set_target_properties(bench_load_volume PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_load_volume PRIVATE vbl_static)

# Issue-8 benchmark: light-path surface VSLs against blue-noise VSLs (N = vsl_lights in
# {4096, 16384, 65536}, with and without the path extension) and pt, at equal time and at equal
# virtual-light count, on the smoky room and a surfaces-only glossy room (bench/bench_blue_noise.c).
# Run: build/bench/bench_blue_noise --budget 30 --csv bench/results/blue_noise.csv
#      /usr/bin/python3 bench/plot_blue_noise.py bench/results/blue_noise.csv docs/images/blue_noise_error_vs_time.png
add_executable(bench_blue_noise ${CMAKE_CURRENT_LIST_DIR}/bench_blue_noise.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_blue_noise PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_blue_noise PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_blue_noise PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_blue_noise PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_blue_noise vbl_sample_cloud)
endif()

# Issue-8 experiment: camera-driven blue-noise placement of the MEDIUM virtual lights of
# volume_from_volume against the classic light-path VPLs (bench/bench_bn_media.c).
# Run (reuses the cached bench_curves pt references of BUILD/bench at the same resolution, else
# renders them): build/bench/bench_bn_media --scenes cloud --passes 128 --budget 20
#                build/bench/bench_bn_media --scenes smoky_room --passes 24 --budget 20
# Results: bench/results/bn_media.txt; summary: docs/readme/blue_noise_media.md.
add_executable(bench_bn_media ${CMAKE_CURRENT_LIST_DIR}/bench_bn_media.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_bn_media PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_bn_media PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_bn_media PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_bn_media PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_bn_media vbl_sample_cloud)
endif()

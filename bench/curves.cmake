# Issue-4/6 benchmark: error-vs-time curves (rMAE against a cached long pt reference) of every
# method and quality preset on the sample cloud, a dense anisotropic cloud and the smoky room
# (bench/bench_curves.c).
# Run: build/bench/bench_curves --budget 30 --csv bench/results/curves.csv
#      (issue 13's light-tree rows: --methods pt,vrl,vbl,vrl-sel,vbl-sel)
#      /usr/bin/python3 bench/plot_curves.py bench/results/curves.csv docs/images/error_vs_time.png
add_executable(bench_curves ${CMAKE_CURRENT_LIST_DIR}/bench_curves.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_curves PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_curves PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_curves PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_curves PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_curves vbl_sample_cloud)
endif()

# Issue-13 measurement: where a vrl / vbl pass spends its time, the cost per camera sample with and
# without light-tree selection, and how many VRLs carry a camera ray's estimate (bench/bench_vrl_profile.c).
# Run: build/bench/bench_vrl_profile --scenes cloud,dense --light-paths 30 --res 32x24 --select 0,1,4,16
add_executable(bench_vrl_profile ${CMAKE_CURRENT_LIST_DIR}/bench_vrl_profile.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_vrl_profile PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_vrl_profile PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_vrl_profile PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_vrl_profile PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  VBL_BENCH_CACHE_DIR="${PROJECT_BINARY_DIR}/bench")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_vrl_profile vbl_sample_cloud)
endif()

# Issue 13, round 2: which factor of the per-VRL estimate makes it heavy-tailed (bench/bench_vrl_tail.c).
# Run: build/bench/bench_vrl_tail --scenes cloud,dense --light-paths 150 --res 32x24 --samples 48
add_executable(bench_vrl_tail ${CMAKE_CURRENT_LIST_DIR}/bench_vrl_tail.c ${CMAKE_CURRENT_LIST_DIR}/bench_reference.c)
set_target_properties(bench_vrl_tail PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_vrl_tail PRIVATE vbl_static OpenMP::OpenMP_C m)
target_include_directories(bench_vrl_tail PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)
target_compile_definitions(bench_vrl_tail PRIVATE
  VBL_BENCH_DEFAULT_VDB="${PROJECT_BINARY_DIR}/samples/cloud.vdb"
  VBL_BENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
if(TARGET vbl_sample_cloud)
  add_dependencies(bench_vrl_tail vbl_sample_cloud)
endif()
# Issue 13 (energy): replicas through the public API (bench_vrl_energy) and per-VRL energies and
# light-tree selection moments (bench_vrl_energy_vrls); results in bench/results/vrl_energy_issue13.txt.
add_executable(bench_vrl_energy ${CMAKE_CURRENT_LIST_DIR}/bench_vrl_energy.c)
set_target_properties(bench_vrl_energy PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_vrl_energy PRIVATE vbl_static m)
add_executable(bench_vrl_energy_vrls ${CMAKE_CURRENT_LIST_DIR}/bench_vrl_energy_vrls.c)
set_target_properties(bench_vrl_energy_vrls PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
target_link_libraries(bench_vrl_energy_vrls PRIVATE vbl_static m)
target_include_directories(bench_vrl_energy_vrls PRIVATE ${PROJECT_SOURCE_DIR}/libvbl/src)

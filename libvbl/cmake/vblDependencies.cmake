# Locates the Debian 12 packages libvbl builds against and defines imported targets for them.
find_package(OpenMP REQUIRED COMPONENTS C CXX)
find_package(TBB REQUIRED CONFIG)
find_package(ZLIB REQUIRED)
find_package(Imath REQUIRED CONFIG)
find_package(cJSON REQUIRED CONFIG)
find_package(PNG REQUIRED)
find_library(VBL_OPENVDB_LIBRARY NAMES openvdb REQUIRED)
find_library(VBL_BLOSC_LIBRARY NAMES blosc REQUIRED)
find_path(VBL_NANOVDB_INCLUDE_DIR nanovdb/PNanoVDB.h REQUIRED)
find_path(VBL_OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)

if(NOT TARGET vbl::openvdb)
  add_library(vbl::openvdb INTERFACE IMPORTED)
  target_include_directories(vbl::openvdb INTERFACE ${VBL_OPENVDB_INCLUDE_DIR} ${VBL_NANOVDB_INCLUDE_DIR})
  target_compile_definitions(vbl::openvdb INTERFACE NANOVDB_USE_BLOSC NANOVDB_USE_ZIP)
  target_link_libraries(vbl::openvdb INTERFACE ${VBL_OPENVDB_LIBRARY} TBB::tbb ${VBL_BLOSC_LIBRARY}
                        ZLIB::ZLIB Imath::Imath Threads::Threads)
endif()
find_package(Threads REQUIRED)

# Surfaces: Embree 3 (ray tracing), assimp (OBJ/PLY meshes, C API), OpenSubdiv Far (CPU).
find_library(VBL_EMBREE_LIBRARY NAMES embree3 REQUIRED)
find_path(VBL_EMBREE_INCLUDE_DIR embree3/rtcore.h REQUIRED)
find_library(VBL_ASSIMP_LIBRARY NAMES assimp REQUIRED)
find_path(VBL_ASSIMP_INCLUDE_DIR assimp/cimport.h REQUIRED)
find_library(VBL_OSDCPU_LIBRARY NAMES osdCPU REQUIRED)
find_path(VBL_OSD_INCLUDE_DIR opensubdiv/far/topologyRefiner.h REQUIRED)
if(NOT TARGET vbl::surfaces)
  add_library(vbl::surfaces INTERFACE IMPORTED)
  target_include_directories(vbl::surfaces INTERFACE ${VBL_EMBREE_INCLUDE_DIR} ${VBL_ASSIMP_INCLUDE_DIR}
                             ${VBL_OSD_INCLUDE_DIR})
  target_link_libraries(vbl::surfaces INTERFACE ${VBL_EMBREE_LIBRARY} ${VBL_ASSIMP_LIBRARY} ${VBL_OSDCPU_LIBRARY})
endif()

/* C interface of the C++ OpenVDB/NanoVDB adapter. The core (C11) calls only these functions;
 * everything C++ stays inside vdb/src. The adapter reads files and hands back NanoVDB float
 * grid buffers; statistics, policies and sampling happen in the C core. */
#ifndef VBL_VDB_ADAPTER_H
#define VBL_VDB_ADAPTER_H

#include <stddef.h>
#include <stdint.h>

#include "vbl/vbl_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads one float grid from a .vdb (OpenVDB, any version/codec/half storage) or .nvdb file and
 * returns it as a NanoVDB float grid in a buffer allocated with vbl_aligned_alloc (the caller
 * frees with vbl_aligned_free). Grid selection follows vbl_volume_load_options (grid_name,
 * grid_index). On failure returns the code and fills `message` with one line naming the file
 * and, for a missing grid, listing the grids in the file. */
vbl_result vbl_vdb_read_float_grid(const char* path, const char* grid_name, int grid_index,
                                   void** out_buffer, size_t* out_size, int* out_file_grid_index,
                                   char* message, size_t message_size);

/* Component `component` (0 x, 1 y, 2 z) of a vec3s/vec3d grid (OpenVDB files; half storage too)
 * as a NanoVDB float grid with the same topology, tile structure, background component and
 * transform; its name is "<grid>.x" / ".y" / ".z". Selection as vbl_vdb_read_float_grid. A float
 * grid fails with VBL_ERROR_GRID_TYPE; a vector grid in a .nvdb file with VBL_ERROR_UNSUPPORTED
 * (docs/readme/vdb.md). */
vbl_result vbl_vdb_read_vec3_component(const char* path, const char* grid_name, int grid_index, int component,
                                       void** out_buffer, size_t* out_size, int* out_file_grid_index,
                                       char* message, size_t message_size);

/* Description of every grid in a file, for `vbl info` (float or not). */
typedef struct vbl_vdb_grid_desc {
    char name[256];
    char type[64];          /* "float", "half float", "vec3s", "int32", ... */
    int is_float;
    uint64_t active_voxels;
    int index_bbox_min[3], index_bbox_max[3];
    double voxel_size[3];
    char codec[64];         /* "blosc + active mask", "zip", "none", ... */
} vbl_vdb_grid_desc;

/* Lists the grids of a .vdb/.nvdb file; *out_grids is malloc'ed (free with free()). */
vbl_result vbl_vdb_list_grids(const char* path, vbl_vdb_grid_desc** out_grids, size_t* out_count,
                              char* message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif

/* Validation of PLY files before they reach assimp: assimp 5.2.5 crashes, aborts or hangs on
 * crafted PLY headers and bodies (fuzzing, issue 18). The check reads the header (keywords,
 * types, element counts below 2^31) and walks the body (every element present, list counts at
 * most 256, face vertex indices below the vertex count), so assimp only sees well-formed files. */
#ifndef VBL_GEOMETRY_MESH_PLY_CHECK_H
#define VBL_GEOMETRY_MESH_PLY_CHECK_H

#include "vbl/vbl_core.h"

/* 1 when the file starts with the PLY magic line ("ply\n" or "ply\r"). */
int vbl_mesh_is_ply(const char* path);

/* VBL_SUCCESS, or VBL_ERROR_CORRUPT_FILE with one message naming the file and the field. */
vbl_result vbl_mesh_check_ply(const char* path);

#endif

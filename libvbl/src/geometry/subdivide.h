/* Subdivision surfaces through OpenSubdiv Far (subdivide_osd.cc, C++17 behind this C header).
 *
 * Scheme: Loop when every face is a triangle, Catmull-Clark otherwise; boundaries interpolate
 * edges and corners (VTX_BOUNDARY_EDGE_AND_CORNER); no creases. The control mesh is refined
 * uniformly `level` times (1..6) and the vertices of the last level are moved to the limit
 * surface, with limit normals (cross product of the limit tangents); Catmull-Clark quads are
 * split into two triangles. Level 0 returns the control polygons fan-triangulated, unchanged.
 * Non-manifold edges and vertices are accepted (OpenSubdiv tags them and treats them like
 * boundaries); index data out of range, faces with fewer than 3 vertices or a vertex repeated
 * within a face, and topology OpenSubdiv rejects are errors. */
#ifndef VBL_GEOMETRY_SUBDIVIDE_H
#define VBL_GEOMETRY_SUBDIVIDE_H

#include <stddef.h>

#include "geometry/surfaces.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_SUBDIVISION_MAX_LEVEL 6

/* positions: 3 * vertex_count; face_sizes[face_count]; indices: sum of face_sizes. On success
 * *out is a triangle mesh with normals (free with vbl_mesh_data_free). `what` names the mesh in
 * messages. */
vbl_result vbl_subdivide(const double* positions, size_t vertex_count, const int* face_sizes, size_t face_count,
                         const int* indices, int level, const char* what, vbl_mesh_data* out);

#ifdef __cplusplus
}
#endif

#endif

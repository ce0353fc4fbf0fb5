/* Mesh files through assimp's C API (OBJ, PLY and whatever else assimp reads). All meshes of
 * the file are merged (node transforms applied); faces that are not triangles after
 * triangulation (points, lines, degenerates found by aiProcess_FindDegenerates) are dropped. */
#ifndef VBL_GEOMETRY_MESH_LOAD_H
#define VBL_GEOMETRY_MESH_LOAD_H

#include "geometry/surfaces.h"

/* A polygon mesh for subdivision: face_sizes[f] vertices per face, indices concatenated. */
typedef struct vbl_poly_mesh {
    double* positions;  /* 3 * vertex_count */
    size_t vertex_count;
    int* face_sizes;
    size_t face_count;
    int* indices;       /* sum of face_sizes */
    size_t index_count;
} vbl_poly_mesh;

void vbl_poly_mesh_free(vbl_poly_mesh* mesh);

/* Triangle mesh with vertex normals when the file has them. Missing file:
 * VBL_ERROR_FILE_NOT_FOUND; unreadable: VBL_ERROR_CORRUPT_FILE; no triangles: VBL_ERROR_SCENE.
 * *dropped counts faces that were not triangles (may be NULL). */
vbl_result vbl_mesh_load(const char* path, vbl_mesh_data* out, size_t* dropped);

/* Polygon mesh (not triangulated, normals/texture coordinates dropped so that vertices are
 * joined by position alone) for subdivision. */
vbl_result vbl_mesh_load_polygons(const char* path, vbl_poly_mesh* out);

#endif

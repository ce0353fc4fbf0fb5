/* Scene surfaces: triangle meshes (OBJ/PLY through assimp's C API, optionally refined with
 * OpenSubdiv Far) in one committed Embree 3 scene, traced from any thread.
 *
 * Owner: geometry/ (surfaces.c: Embree device + scene; mesh_load.c: assimp; subdivide.h /
 * subdivide_osd.cc: OpenSubdiv behind extern "C"). */
#ifndef VBL_GEOMETRY_SURFACES_H
#define VBL_GEOMETRY_SURFACES_H

#include <stddef.h>

#include "core/math.h"
#include "vbl/vbl_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vbl_surfaces vbl_surfaces;

typedef struct vbl_surface_hit {
    double t;                  /* ray parameter of the hit */
    vbl_vec3 position;
    vbl_vec3 geometric_normal; /* unit, facing the incoming ray (dot(ng, d) < 0) */
    vbl_vec3 shading_normal;   /* unit, interpolated vertex normal flipped to ng's side (= ng without normals) */
    int surface;               /* index into scene surfaces[] */
    int material;              /* index into scene materials[] */
} vbl_surface_hit;

/* Closest hit with t in (t_min, t_max) (t_max may be INFINITY); 0 if none. NULL surfaces: 0. */
int vbl_surfaces_intersect(const vbl_surfaces* s, vbl_vec3 origin, vbl_vec3 direction, double t_min, double t_max,
                           vbl_surface_hit* hit);
/* 1 if anything blocks (t_min, t_max). NULL surfaces: 0. */
int vbl_surfaces_occluded(const vbl_surfaces* s, vbl_vec3 origin, vbl_vec3 direction, double t_min, double t_max);
/* Ray casts (intersect + occluded calls that reach Embree) made by the calling thread so far: a
 * deterministic cost count (render.hybrid's pilot, render/hybrid.h). */
uint64_t vbl_surfaces_ray_count(void);

/* Offset for spawning rays off a surface point without self-intersection (scale-aware). */
double vbl_surfaces_ray_epsilon(const vbl_surfaces* s, vbl_vec3 position);

void vbl_surfaces_release(vbl_surfaces* s);

/* ---- building (single-threaded, before rendering) ------------------------------------- */

/* A triangle mesh in scene space. normals: per-vertex (NULL: geometric normals are used). */
typedef struct vbl_mesh_data {
    double* positions;      /* 3 * vertex_count */
    double* normals;        /* 3 * vertex_count or NULL */
    size_t vertex_count;
    unsigned* indices;      /* 3 * triangle_count */
    size_t triangle_count;
} vbl_mesh_data;

void vbl_mesh_data_free(vbl_mesh_data* mesh);

/* Creates an empty Embree device + scene (RTC_SCENE_FLAG_ROBUST). `name` is used in messages. */
vbl_result vbl_surfaces_create(const char* name, vbl_surfaces** out);
/* Adds `mesh` (copied) as surface number vbl_surfaces_count() with `material`, transformed by
 * `to_scene` (NULL: identity; normals by its inverse transpose) and commits the scene. Triangles
 * with zero area (after the transform), repeated or out-of-range indices are dropped and counted
 * in *dropped (may be NULL); a mesh left with no triangle is an error naming `what`. */
vbl_result vbl_surfaces_add_mesh(vbl_surfaces* s, const vbl_mesh_data* mesh, int material, const vbl_affine* to_scene,
                                 const char* what, size_t* dropped);
int vbl_surfaces_count(const vbl_surfaces* s);
size_t vbl_surfaces_triangle_count(const vbl_surfaces* s);
/* Axis-aligned bounds of all triangles (scene space); returns 0 when empty. */
int vbl_surfaces_bounds(const vbl_surfaces* s, vbl_vec3* lo, vbl_vec3* hi);

#ifdef __cplusplus
}
#endif

#endif

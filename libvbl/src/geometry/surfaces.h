/* Scene surfaces: triangle meshes (OBJ/PLY through assimp's C API, optionally refined with
 * OpenSubdiv Far) in one committed Embree 3 scene, traced from any thread.
 *
 * Owner: geometry/ (surfaces.c: Embree device + scene; mesh_load.c: assimp; subdivide.h /
 * subdivide_osd.cc: OpenSubdiv behind extern "C"). */
#ifndef VBL_GEOMETRY_SURFACES_H
#define VBL_GEOMETRY_SURFACES_H

#include "core/math.h"

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

/* Offset for spawning rays off a surface point without self-intersection (scale-aware). */
double vbl_surfaces_ray_epsilon(const vbl_surfaces* s, vbl_vec3 position);

void vbl_surfaces_release(vbl_surfaces* s);

#endif

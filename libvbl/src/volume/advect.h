/* Eulerian advection for velocity motion blur (docs/readme/emission.md "Motion blur"): a field
 * f seen at time t (seconds relative to the frame) is f(x - v(x) t), as Cycles and Arnold sample
 * a velocity grid; v in the file's world units per second. */
#ifndef VBL_VOLUME_ADVECT_H
#define VBL_VOLUME_ADVECT_H

#include "volume/grid_sample.h"

/* A velocity grid as three float component volumes (vec3s split at load, or Houdini's
 * vel.x/vel.y/vel.z), times `scale`. v[0] NULL: no velocity. */
typedef struct vbl_velocity_field {
    const vbl_volume* v[3];
    double scale;
    double max_speed; /* >= |v(x)| everywhere (trilinear of vectors stays in their convex hull) */
} vbl_velocity_field;

/* x - v(x) time, v trilinear in each component volume's own world space (x is in that same
 * file world space). acc: three accessors on f->v (NULL: local ones, slower). No velocity or
 * time == 0: x itself, bit for bit. */
vbl_vec3 vbl_velocity_advect(const vbl_velocity_field* f, vbl_grid_accessor* acc, vbl_vec3 x, double time);

/* Largest |v| over the voxels of the three components (a bound, per voxel, of the true norm;
 * times f->scale). */
double vbl_velocity_max_speed(const vbl_velocity_field* f);

#endif

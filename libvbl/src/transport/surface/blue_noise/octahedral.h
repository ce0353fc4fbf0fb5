/* Octahedral direction map (Engelhardt and Dachsbacher 2008), the per-light directional table
 * of Li et al. 2022, section 5 (16 x 16 cells by default): the unit sphere is
 * projected onto the octahedron |x| + |y| + |z| = 1, the upper half (z >= 0) unfolds onto the
 * diamond |u'| + |v'| <= 1 of [-1, 1]^2 and the lower half onto the four corners.
 * Directions are in any frame the caller chooses (the blue-noise lights use their local frame,
 * normal = +z). Cells are indexed cell = row * res + column, (u, v) in [0, 1]^2. */
#ifndef VBL_BLUE_NOISE_OCTAHEDRAL_H
#define VBL_BLUE_NOISE_OCTAHEDRAL_H

#include "core/math.h"
#include "vbl/vbl_core.h"

#define VBL_BN_OCT_RESOLUTION_DEFAULT 16
#define VBL_BN_OCT_RESOLUTION_MAX 256

/* Direction (any non-zero length) -> (u, v) in [0, 1]^2. */
void vbl_oct_encode(vbl_vec3 d, double* u, double* v);
/* (u, v) in [0, 1]^2 -> unit direction (inverse of vbl_oct_encode). */
vbl_vec3 vbl_oct_decode(double u, double v);
/* Cell of a direction on a res x res map. */
int vbl_oct_cell(vbl_vec3 d, int res);
/* Unit direction of the centre of a cell. */
vbl_vec3 vbl_oct_cell_center(int cell, int res);

/* Per-cell tables for one resolution:
 *   solid_angle[c]: exact solid angle (each cell is split into triangles lying on one octahedron
 *                   face, whose radial projections are spherical triangles); sums to 4 pi;
 *   direction[c]:   unit solid-angle-weighted mean direction of the cell's part with z > 0
 *                   (of the whole cell when it lies below), so cells cut by the horizon still
 *                   have a representative direction strictly above it;
 *   upper[c]:       solid angle of the cell's part with z > 0. */
typedef struct vbl_oct_table {
    int resolution;
    double* solid_angle;
    double* upper;
    vbl_vec3* direction;
} vbl_oct_table;

/* res must be even in [2, VBL_BN_OCT_RESOLUTION_MAX]; error names `res`. */
vbl_result vbl_oct_table_init(vbl_oct_table* table, int res);
void vbl_oct_table_free(vbl_oct_table* table);

#endif

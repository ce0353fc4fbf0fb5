/* Camera importance over the media for steering light paths (vrl.light_guide; issue 13).
 *
 * Vorba and Krivanek 2016, "Adjoint-driven Russian roulette and splitting in light transport
 * simulation", sec. 4-5, with the camera's importance as the adjoint: a light path of weight Phi
 * at x is split when Phi I(x) is above a target and rouletted when below (photon_trace.c).
 *
 * I(x) here is a coarse estimate, deterministic per render (no random numbers at all): a regular
 * grid of VBL_CAMERA_IMPORTANCE_RAYS_X x _Y camera rays through the image is marched through the
 * media in steps of half a voxel, each step depositing the probability that the camera ray
 * scatters there, T_c(u) (1 - exp(-sigma_t h)) albedo (= int T_c sigma_s du over the step), into
 * a VBL_CAMERA_IMPORTANCE_RES^3 voxel grid over the media's bounding cube. The grid is then
 * blurred (two 3-tap box passes per axis, about two voxels), since a VRL lights camera points
 * near it through 1/w^2, and a floor of VBL_CAMERA_IMPORTANCE_FLOOR times the mean importance is
 * added so that no region has zero importance (paths there are rouletted, never cut). The grid
 * depends only on the scene and the camera, so split/merge and thread counts are unaffected. */
#ifndef VBL_TRANSPORT_CAMERA_IMPORTANCE_H
#define VBL_TRANSPORT_CAMERA_IMPORTANCE_H

#include "transport/common/estimator.h"

#define VBL_CAMERA_IMPORTANCE_RES 32
#define VBL_CAMERA_IMPORTANCE_RAYS_X 64
#define VBL_CAMERA_IMPORTANCE_RAYS_Y 48
#define VBL_CAMERA_IMPORTANCE_FLOOR 0.1

typedef struct vbl_camera_importance {
    vbl_vec3 lo;        /* grid origin (the media's bounding cube) */
    double voxel;       /* voxel edge in scene units */
    int res;            /* voxels per axis */
    float* value;       /* res^3, x fastest; the blurred deposit (no floor) */
    double total;       /* sum of value (0: the camera sees no scattering medium) */
} vbl_camera_importance;

/* Builds the grid for ctx's scene and camera (single-threaded, ctx->scene's media and surfaces).
 * Returns 0 when there are no media or out of memory (g zeroed). */
int vbl_camera_importance_build(const vbl_render_context* ctx, vbl_camera_importance* g);
void vbl_camera_importance_free(vbl_camera_importance* g);

/* The (blurred) importance of the voxel containing x; 0 outside the grid. */
static inline double vbl_camera_importance_at(const vbl_camera_importance* g, vbl_vec3 x)
{
    if (!g->value) return 0.0;
    const double s = 1.0 / g->voxel;
    const double fx = (x.x - g->lo.x) * s, fy = (x.y - g->lo.y) * s, fz = (x.z - g->lo.z) * s;
    if (!(fx >= 0.0 && fy >= 0.0 && fz >= 0.0 && fx < g->res && fy < g->res && fz < g->res)) return 0.0;
    const int i = (int)fx, j = (int)fy, k = (int)fz;
    return g->value[((size_t)k * (size_t)g->res + (size_t)j) * (size_t)g->res + (size_t)i];
}

#endif

/* Helpers for the virtual-light tests: small scenes, replicated renders and block statistics. */
#ifndef VBL_TRANSPORT_TEST_UTIL_H
#define VBL_TRANSPORT_TEST_UTIL_H

#include "render/render_internal.h"
#include "scene/scene.h"

#define TT_MAX_BLOCKS 64
#define TT_LAYERS 2 /* volume_direct, volume_from_volume */

/* Block means (mean of R,G,B over b x b pixel blocks) of the two scattering layers, averaged over
 * K independent renders (different seeds), with standard errors from the spread of the renders. */
typedef struct tt_stats {
    int blocks;
    double mean[TT_LAYERS][TT_MAX_BLOCKS], se[TT_LAYERS][TT_MAX_BLOCKS];
    double image_mean[TT_LAYERS], image_se[TT_LAYERS];
    int finite;
} tt_stats;

void tt_replicate(const vbl_scene* scene, const vbl_estimator* est, const vbl_render_options* options, int K,
                  int block, tt_stats* out);
/* Largest |z| over blocks and layers of (a - scale_b * b) (scale applied to b's volume_from_volume
 * only); *image_z receives the largest |z| of the image means. */
double tt_compare(const tt_stats* a, const tt_stats* b, double scale_b_from_volume, double* image_z, const char* tag);

vbl_scene* tt_scene(const vbl_camera* cam);
void tt_add_point(vbl_scene* s, vbl_vec3 p, double I);
void tt_add_spot(vbl_scene* s, vbl_vec3 p, vbl_vec3 dir, double I, double inner_deg, double outer_deg);
void tt_add_distant(vbl_scene* s, vbl_vec3 dir, double E);
/* A smooth heterogeneous sphere of radius r at the origin (procedural in-memory grid, n^3 voxels):
 * density (1 - (|x|/r)^2)^2 inside, 0 outside. */
vbl_volume* tt_make_sphere(int n, double r);

vbl_render_options tt_options(int passes, int spp, int light_paths, uint64_t seed);
int tt_film_finite(const vbl_film* film);

#endif

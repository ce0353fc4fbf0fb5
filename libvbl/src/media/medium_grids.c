/* Albedo grids and advected role-grid lookups (medium_grids.h). Lookups use local PNanoVDB
 * accessors (their set-up is a few stores), so the medium interface needs no extra cursor. */
#include "media/medium_grids.h"

#include "volume/advect.h"
#include "volume/grid_sample.h"

vbl_vec3 vbl_medium_grid_point(const vbl_scene* scene, int i, vbl_vec3 p, double time)
{
    const vbl_medium* m = &scene->media[i];
    vbl_vec3 q = vbl_affine_point(&m->scene_to_volume, p);
    if (time != 0.0 && m->velocity.v[0]) q = vbl_velocity_advect(&m->velocity, NULL, q, time);
    return q;
}

vbl_vec3 vbl_medium_albedo_at(const vbl_scene* scene, int i, vbl_vec3 p, double time)
{
    const vbl_medium* m = &scene->media[i];
    if (!m->albedo_volume[0]) return m->albedo;
    vbl_vec3 q = vbl_medium_grid_point(scene, i, p, time);
    double a[3];
    for (int c = 0; c < 3; ++c) {
        if (c > 0 && m->albedo_volume[c] == m->albedo_volume[0]) { /* a grey (float) grid */
            a[c] = a[0];
            continue;
        }
        vbl_grid_accessor acc;
        vbl_grid_accessor_init(&acc, m->albedo_volume[c]);
        a[c] = vbl_grid_sample_world(&acc, q, VBL_FILTER_TRILINEAR);
        if (!(a[c] > 0.0)) a[c] = 0.0; /* trilinear of values >= 0 is >= 0; guards -0 */
    }
    return vbl_v3(m->albedo.x * a[0], m->albedo.y * a[1], m->albedo.z * a[2]);
}

void vbl_medium_point_apply_grids(const vbl_scene* scene, vbl_vec3 p, double time, vbl_medium_point* mp)
{
    if (!scene->has_albedo_grids || mp->count == 0) return;
    vbl_vec3 sigma_s = vbl_v3(0.0, 0.0, 0.0);
    for (int k = 0; k < mp->count; ++k) {
        vbl_phase_lobe* l = &mp->lobe[k];
        if (scene->media[l->medium].albedo_volume[0]) l->albedo = vbl_medium_albedo_at(scene, l->medium, p, time);
        sigma_s = vbl_v3_madd(sigma_s, l->albedo, l->sigma_t);
    }
    mp->sigma_s = sigma_s;
}

/* The medium point query and the sigma_s-weighted HG mixture on it (medium.h). */
#include "media/medium.h"

#include "media/medium_grids.h"
#include "sampling/phase_hg.h"

static double vbl_mean3(vbl_vec3 v) { return (v.x + v.y + v.z) * (1.0 / 3.0); }

void vbl_medium_point_from_components(const vbl_scene* scene, const double* component_sigma_t, vbl_medium_point* out)
{
    out->sigma_t = 0.0;
    out->sigma_s = vbl_v3(0.0, 0.0, 0.0);
    out->count = 0;
    for (int i = 0; i < scene->media_count && i < VBL_MAX_MEDIA; ++i) {
        const double st = component_sigma_t[i];
        if (!(st > 0.0)) continue;
        vbl_phase_lobe* l = &out->lobe[out->count++];
        l->medium = i;
        l->sigma_t = st;
        l->albedo = scene->media[i].albedo;
        l->g = scene->media[i].g;
        out->sigma_t += st;
        out->sigma_s = vbl_v3_madd(out->sigma_s, l->albedo, st);
    }
}

double vbl_medium_query(const vbl_scene* scene, const vbl_extinction* extinction, vbl_extinction_cursor* cursor,
                        vbl_vec3 p, vbl_medium_point* out)
{
    double comps[VBL_MAX_MEDIA];
    double sigma_t = vbl_extinction_eval(extinction, cursor, p, comps);
    if (!(sigma_t > 0.0)) {
        out->sigma_t = 0.0;
        out->sigma_s = vbl_v3(0.0, 0.0, 0.0);
        out->count = 0;
        return 0.0;
    }
    vbl_medium_point_from_components(scene, comps, out);
    out->sigma_t = sigma_t; /* the field's own sum (bit-identical to what callers used before) */
    vbl_medium_point_apply_grids(scene, p, cursor->time, out);
    return sigma_t;
}

vbl_vec3 vbl_medium_phase_kernel(const vbl_medium_point* mp, double cos_theta)
{
    vbl_vec3 k = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < mp->count; ++i)
        k = vbl_v3_madd(k, mp->lobe[i].albedo, mp->lobe[i].sigma_t * vbl_hg_eval(mp->lobe[i].g, cos_theta));
    return k;
}

double vbl_medium_phase_pdf(const vbl_medium_point* mp, double cos_theta)
{
    double total = 0.0, pdf = 0.0;
    for (int i = 0; i < mp->count; ++i) {
        double w = mp->lobe[i].sigma_t * vbl_mean3(mp->lobe[i].albedo);
        total += w;
        if (w > 0.0) pdf += w * vbl_hg_pdf(mp->lobe[i].g, cos_theta);
    }
    return total > 0.0 ? pdf / total : 0.0;
}

int vbl_medium_phase_sample(const vbl_medium_point* mp, vbl_vec3 travel, double u0, double u1, double u2,
                            vbl_vec3* wi, double* pdf)
{
    double weights[VBL_MAX_MEDIA], total = 0.0;
    int last = -1;
    for (int i = 0; i < mp->count; ++i) {
        weights[i] = mp->lobe[i].sigma_t * vbl_mean3(mp->lobe[i].albedo);
        total += weights[i];
        if (weights[i] > 0.0) last = i;
    }
    if (!(total > 0.0)) return 0;
    int pick = last;
    double target = u0 * total, acc = 0.0;
    for (int i = 0; i < mp->count; ++i) {
        acc += weights[i];
        if (weights[i] > 0.0 && target < acc) {
            pick = i;
            break;
        }
    }
    double lobe_pdf = 0.0;
    *wi = vbl_hg_sample(mp->lobe[pick].g, travel, u1, u2, &lobe_pdf);
    *pdf = mp->count == 1 ? lobe_pdf : vbl_medium_phase_pdf(mp, vbl_v3_dot(travel, *wi));
    return *pdf > 0.0;
}

double vbl_medium_mean_g(const vbl_medium_point* mp)
{
    double w = 0.0, g = 0.0;
    for (int i = 0; i < mp->count; ++i) {
        const vbl_vec3 a = mp->lobe[i].albedo;
        double s = mp->lobe[i].sigma_t * (a.x + a.y + a.z);
        w += s;
        g += s * mp->lobe[i].g;
    }
    return w > 0.0 ? g / w : 0.0;
}

void vbl_medium_point_scene(const vbl_scene* scene, vbl_medium_point* out)
{
    double scale[VBL_MAX_MEDIA] = {0};
    for (int i = 0; i < scene->media_count && i < VBL_MAX_MEDIA; ++i) scale[i] = scene->media[i].density_scale;
    vbl_medium_point_from_components(scene, scale, out);
}

int vbl_medium_free_flight(const vbl_scene* scene, const vbl_extinction* extinction, vbl_extinction_cursor* cursor,
                           const vbl_segment* segment, int use_global_majorant, vbl_rng* rng, double* t,
                           vbl_medium_point* out)
{
    double comps[VBL_MAX_MEDIA] = {0}, sigma_t = 0.0;
    if (!vbl_free_flight_sample(extinction, cursor, segment->origin, segment->direction, segment->t0, segment->t1,
                                use_global_majorant, rng, t, &sigma_t, comps))
        return 0;
    vbl_medium_point_from_components(scene, comps, out);
    out->sigma_t = sigma_t; /* the tracker's own sum (what callers divided by before) */
    vbl_medium_point_apply_grids(scene, vbl_segment_at(segment, *t), cursor->time, out); /* albedo grids */
    return 1;
}

int vbl_medium_scatter(const vbl_medium_point* mp, vbl_vec3 travel, const double u[3], vbl_vec3* wi, double* pdf,
                       vbl_vec3* throughput)
{
    double p = 0.0;
    if (!vbl_medium_phase_sample(mp, travel, u[0], u[1], u[2], wi, &p)) return 0;
    if (pdf) *pdf = p;
    vbl_vec3 kernel = vbl_medium_phase_kernel(mp, vbl_v3_dot(travel, *wi));
    *throughput = vbl_v3_scale(vbl_v3_mul(*throughput, kernel), 1.0 / (p * mp->sigma_t));
    return 1;
}

/* sigma_s-weighted HG mixtures of overlapping media (issue 3: "phase mixed by sigma_s"). */
#include "media/media.h"

#include "sampling/phase_hg.h"

static double vbl_mean3(vbl_vec3 v) { return (v.x + v.y + v.z) * (1.0 / 3.0); }

vbl_vec3 vbl_media_scatter_kernel(const vbl_scene* scene, const double* component_sigma_t, double cos_theta)
{
    vbl_vec3 k = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < scene->media_count; ++i) {
        double st = component_sigma_t[i];
        if (!(st > 0.0)) continue;
        k = vbl_v3_madd(k, scene->media[i].albedo, st * vbl_hg_eval(scene->media[i].g, cos_theta));
    }
    return k;
}

double vbl_media_phase_pdf(const vbl_scene* scene, const double* component_sigma_t, double cos_theta)
{
    double total = 0.0, pdf = 0.0;
    for (int i = 0; i < scene->media_count; ++i) {
        double w = component_sigma_t[i] > 0.0 ? component_sigma_t[i] * vbl_mean3(scene->media[i].albedo) : 0.0;
        total += w;
        if (w > 0.0) pdf += w * vbl_hg_pdf(scene->media[i].g, cos_theta);
    }
    return total > 0.0 ? pdf / total : 0.0;
}

int vbl_media_sample_phase(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 travel,
                           double u0, double u1, double u2, vbl_vec3* wi, double* pdf)
{
    double weights[VBL_MAX_MEDIA], total = 0.0;
    int last = -1;
    for (int i = 0; i < scene->media_count; ++i) {
        weights[i] = component_sigma_t[i] > 0.0 ? component_sigma_t[i] * vbl_mean3(scene->media[i].albedo) : 0.0;
        total += weights[i];
        if (weights[i] > 0.0) last = i;
    }
    if (!(total > 0.0)) return 0;
    int pick = last;
    double target = u0 * total, acc = 0.0;
    for (int i = 0; i < scene->media_count; ++i) {
        acc += weights[i];
        if (weights[i] > 0.0 && target < acc) {
            pick = i;
            break;
        }
    }
    double lobe_pdf = 0.0;
    *wi = vbl_hg_sample(scene->media[pick].g, travel, u1, u2, &lobe_pdf);
    if (scene->media_count == 1) {
        *pdf = lobe_pdf;
    } else {
        *pdf = vbl_media_phase_pdf(scene, component_sigma_t, vbl_v3_dot(travel, *wi));
    }
    return *pdf > 0.0;
}

int vbl_media_scatter(const vbl_scene* scene, const double* component_sigma_t, double sigma_t, vbl_vec3 travel,
                      double u0, double u1, double u2, vbl_vec3* wi, double* pdf, vbl_vec3* throughput)
{
    double p = 0.0;
    if (!vbl_media_sample_phase(scene, component_sigma_t, travel, u0, u1, u2, wi, &p)) return 0;
    if (pdf) *pdf = p;
    vbl_vec3 kernel = vbl_media_scatter_kernel(scene, component_sigma_t, vbl_v3_dot(travel, *wi));
    *throughput = vbl_v3_scale(vbl_v3_mul(*throughput, kernel), 1.0 / (p * sigma_t));
    return 1;
}

/* sigma_s-weighted HG mixtures of overlapping media (issue 3: "phase mixed by sigma_s"), on
 * per-component sigma_t arrays: thin wrappers of the medium interface (media/medium.h). */
#include "media/media.h"

#include "media/medium.h"
#include "media/medium_grids.h"

vbl_vec3 vbl_media_scatter_kernel(const vbl_scene* scene, const double* component_sigma_t, double cos_theta)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    return vbl_medium_phase_kernel(&mp, cos_theta);
}

double vbl_media_phase_pdf(const vbl_scene* scene, const double* component_sigma_t, double cos_theta)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    return vbl_medium_phase_pdf(&mp, cos_theta);
}

int vbl_media_sample_phase(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 travel,
                           double u0, double u1, double u2, vbl_vec3* wi, double* pdf)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    return vbl_medium_phase_sample(&mp, travel, u0, u1, u2, wi, pdf);
}

int vbl_media_scatter(const vbl_scene* scene, const double* component_sigma_t, double sigma_t, vbl_vec3 travel,
                      double u0, double u1, double u2, vbl_vec3* wi, double* pdf, vbl_vec3* throughput)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    mp.sigma_t = sigma_t;
    const double u[3] = {u0, u1, u2};
    return vbl_medium_scatter(&mp, travel, u, wi, pdf, throughput);
}

double vbl_media_mean_g(const vbl_scene* scene, const double* component_sigma_t)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    return vbl_medium_mean_g(&mp);
}

vbl_vec3 vbl_media_scatter_kernel_at(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 p, double time,
                                     double cos_theta)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    vbl_medium_point_apply_grids(scene, p, time, &mp);
    return vbl_medium_phase_kernel(&mp, cos_theta);
}

int vbl_media_scatter_at(const vbl_scene* scene, const double* component_sigma_t, vbl_vec3 p, double time,
                         double sigma_t, vbl_vec3 travel, double u0, double u1, double u2, vbl_vec3* wi, double* pdf,
                         vbl_vec3* throughput)
{
    vbl_medium_point mp;
    vbl_medium_point_from_components(scene, component_sigma_t, &mp);
    vbl_medium_point_apply_grids(scene, p, time, &mp);
    double q = 0.0;
    if (!vbl_medium_phase_sample(&mp, travel, u0, u1, u2, wi, &q)) return 0;
    if (pdf) *pdf = q;
    vbl_vec3 kernel = vbl_medium_phase_kernel(&mp, vbl_v3_dot(travel, *wi));
    *throughput = vbl_v3_scale(vbl_v3_mul(*throughput, kernel), 1.0 / (q * sigma_t));
    return 1;
}

/* Photon emission sampling per light type and visible emission along camera rays
 * (derivations in light_emission.h). */
#include "transport/common/light_emission.h"

#include <math.h>

#include "media/media_emission.h"
#include "media/medium_grids.h"
#include "sampling/sphere.h"
#include "volume/volume.h"
#include "scene/lights.h"

static double vbl_mean3(vbl_vec3 v) { return (v.x + v.y + v.z) * (1.0 / 3.0); }

int vbl_media_bounding_sphere(const vbl_scene* scene, vbl_vec3* center, double* radius)
{
    vbl_vec3 lo = vbl_v3(INFINITY, INFINITY, INFINITY), hi = vbl_v3(-INFINITY, -INFINITY, -INFINITY);
    int any = 0;
    for (int m = 0; m < scene->media_count; ++m) {
        const vbl_medium* med = &scene->media[m];
        /* the root's active index box, one voxel of margin for the trilinear support */
        const vbl_volume* vol = med->volume;
        pnanovdb_coord_t bmin = pnanovdb_root_get_bbox_min(vol->buf, vol->root);
        pnanovdb_coord_t bmax = pnanovdb_root_get_bbox_max(vol->buf, vol->root);
        if (bmin.x > bmax.x || bmin.y > bmax.y || bmin.z > bmax.z) continue;
        int lo_i[3] = {bmin.x, bmin.y, bmin.z}, hi_i[3] = {bmax.x, bmax.y, bmax.z};
        for (int c = 0; c < 8; ++c) {
            double idx[3];
            for (int a = 0; a < 3; ++a) idx[a] = (c >> a) & 1 ? hi_i[a] + 1.0 : lo_i[a] - 1.0;
            vbl_vec3 p = vbl_affine_point(&med->volume->index_to_world, vbl_v3(idx[0], idx[1], idx[2]));
            p = vbl_affine_point(&med->volume_to_scene, p);
            if (!(isfinite(p.x) && isfinite(p.y) && isfinite(p.z))) continue;
            lo = vbl_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
            hi = vbl_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
            any = 1;
        }
    }
    if (!any) return 0;
    *center = vbl_v3_scale(vbl_v3_add(lo, hi), 0.5);
    /* slightly enlarged so that rays grazing the box are still inside the disc */
    *radius = 0.5 * vbl_v3_length(vbl_v3_sub(hi, lo)) * 1.001 + 1e-9;
    return 1;
}

/* Uniform point on the disc of radius r about `center` perpendicular to unit `axis`. */
static vbl_vec3 vbl_disc_point(vbl_vec3 center, vbl_vec3 axis, double r, double u1, double u2)
{
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    double rho = r * sqrt(u1), phi = 2.0 * VBL_PI * u2;
    return vbl_v3_add(center, vbl_v3_add(vbl_v3_scale(t, rho * cos(phi)), vbl_v3_scale(b, rho * sin(phi))));
}

/* The cone point/spot photons are emitted in (uniformly, solid angle 2 pi one_minus): the
 * narrowest of the whole sphere, the spot's outer cone and the cone subtending the media's
 * bounding sphere (when the light is outside it). Every direction that carries light into the
 * media lies in each of them, so the estimate stays unbiased. */
static void vbl_emission_cone(const vbl_light* light, vbl_vec3 center, double radius, vbl_vec3* axis, double* one_minus)
{
    *axis = vbl_v3(0.0, 0.0, 1.0);
    *one_minus = 2.0;
    if (light->type == VBL_LIGHT_SPOT) {
        *axis = light->direction;
        *one_minus = 1.0 - light->cos_outer;
    }
    vbl_vec3 to = vbl_v3_sub(center, light->position);
    double dist = vbl_v3_length(to);
    if (radius > 0.0 && dist > radius * 1.0001) {
        double s = radius / dist;
        double om = s * s / (1.0 + sqrt(fmax(0.0, 1.0 - s * s))); /* 1 - cos(alpha), cancellation-free */
        if (om < *one_minus) {
            *one_minus = om;
            *axis = vbl_v3_scale(to, 1.0 / dist);
        }
    }
}

int vbl_light_sample_emission(const vbl_light* light, vbl_vec3 sphere_center, double sphere_radius,
                              const double u[4], vbl_emission_sample* out)
{
    switch (light->type) {
    case VBL_LIGHT_POINT:
    case VBL_LIGHT_SPOT: {
        vbl_vec3 axis;
        double one_minus;
        vbl_emission_cone(light, sphere_center, sphere_radius, &axis, &one_minus);
        if (!(one_minus > 0.0)) return 0;
        double cos_t = 1.0 - u[0] * one_minus;
        double sin_t = sqrt(fmax(0.0, 1.0 - cos_t * cos_t));
        double phi = 2.0 * VBL_PI * u[1];
        vbl_vec3 t, b;
        vbl_v3_basis(axis, &t, &b);
        out->origin = light->position;
        out->direction = vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(axis, cos_t),
                                                     vbl_v3_add(vbl_v3_scale(t, sin_t * cos(phi)),
                                                                vbl_v3_scale(b, sin_t * sin(phi)))));
        double falloff = 1.0;
        if (light->type == VBL_LIGHT_SPOT) {
            falloff = vbl_spot_falloff(light, vbl_v3_dot(out->direction, light->direction));
            if (!(falloff > 0.0)) return 0;
        }
        out->flux = vbl_v3_scale(light->color, 2.0 * VBL_PI * one_minus * falloff);
        return 1;
    }
    case VBL_LIGHT_DISTANT: {
        vbl_vec3 d = light->direction;
        vbl_vec3 c = vbl_v3_madd(sphere_center, d, -sphere_radius);
        out->origin = vbl_disc_point(c, d, sphere_radius, u[0], u[1]);
        out->direction = d;
        out->flux = vbl_v3_scale(light->color, VBL_PI * sphere_radius * sphere_radius);
        return 1;
    }
    case VBL_LIGHT_QUAD: {
        if (!(light->area > 0.0)) return 0;
        out->origin = vbl_v3_add(light->corner,
                                 vbl_v3_add(vbl_v3_scale(light->edge1, u[0]), vbl_v3_scale(light->edge2, u[1])));
        /* cosine-weighted hemisphere about the normal (Malley) */
        double rho = sqrt(u[2]), phi = 2.0 * VBL_PI * u[3];
        double z = sqrt(fmax(0.0, 1.0 - u[2]));
        if (!(z > 0.0)) return 0;
        vbl_vec3 t, b;
        vbl_v3_basis(light->normal, &t, &b);
        out->direction = vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(light->normal, z),
                                                     vbl_v3_add(vbl_v3_scale(t, rho * cos(phi)),
                                                                vbl_v3_scale(b, rho * sin(phi)))));
        out->flux = vbl_v3_scale(light->color, light->area * VBL_PI);
        return 1;
    }
    case VBL_LIGHT_ENVIRONMENT: {
        double pdf = 0.0;
        vbl_vec3 d = vbl_sample_uniform_sphere(u[0], u[1], &pdf);
        vbl_vec3 c = vbl_v3_madd(sphere_center, d, -sphere_radius);
        out->origin = vbl_disc_point(c, d, sphere_radius, u[2], u[3]);
        out->direction = d;
        out->flux = vbl_v3_scale(light->color, 4.0 * VBL_PI * VBL_PI * sphere_radius * sphere_radius);
        return 1;
    }
    }
    return 0;
}

double vbl_light_power(const vbl_light* light, vbl_vec3 center, double sphere_radius)
{
    double c = vbl_mean3(light->color);
    switch (light->type) {
    case VBL_LIGHT_POINT:
    case VBL_LIGHT_SPOT: {
        vbl_vec3 axis;
        double one_minus;
        vbl_emission_cone(light, center, sphere_radius, &axis, &one_minus);
        return c * 2.0 * VBL_PI * fmax(0.0, one_minus);
    }
    case VBL_LIGHT_DISTANT: return c * VBL_PI * sphere_radius * sphere_radius;
    case VBL_LIGHT_QUAD: return c * light->area * VBL_PI;
    case VBL_LIGHT_ENVIRONMENT: return c * 4.0 * VBL_PI * VBL_PI * sphere_radius * sphere_radius;
    }
    return 0.0;
}

void vbl_add_visible_emission(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                              vbl_vec3 direction, vbl_rng* rng, vbl_sample_value* out)
{
    const vbl_scene* scene = ctx->scene;
    if (!scene->has_visible_lights) return;
    vbl_vec3* L = &out->L[VBL_CLASS_EMISSION];
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* light = &scene->lights[i];
        double t_hit = INFINITY;
        if (light->type == VBL_LIGHT_QUAD) {
            if (!vbl_quad_intersect(light, origin, direction, &t_hit)) continue;
        } else if (light->type != VBL_LIGHT_ENVIRONMENT) {
            continue;
        }
        double T = vbl_ctx_transmittance(ctx, ts, origin, direction, t_hit, rng);
        *L = vbl_v3_madd(*L, light->color, T);
    }
}

int vbl_photon_emission_sphere(const vbl_scene* scene, int with_media, vbl_vec3* center, double* radius)
{
    const int have_media = with_media && vbl_media_bounding_sphere(scene, center, radius);
    vbl_vec3 slo, shi;
    if (!scene->surfaces || !vbl_surfaces_bounds(scene->surfaces, &slo, &shi)) return have_media;
    vbl_vec3 lo = slo, hi = shi;
    if (have_media) {
        vbl_vec3 r = vbl_v3(*radius, *radius, *radius);
        vbl_vec3 mlo = vbl_v3_sub(*center, r), mhi = vbl_v3_add(*center, r);
        lo = vbl_v3(fmin(mlo.x, slo.x), fmin(mlo.y, slo.y), fmin(mlo.z, slo.z));
        hi = vbl_v3(fmax(mhi.x, shi.x), fmax(mhi.y, shi.y), fmax(mhi.z, shi.z));
    }
    *center = vbl_v3_scale(vbl_v3_add(lo, hi), 0.5);
    *radius = 0.5 * vbl_v3_length(vbl_v3_sub(hi, lo)) * 1.001 + 1e-9;
    return 1;
}

double vbl_photon_source_init(vbl_photon_source* s, const vbl_scene* scene, vbl_vec3 center, double radius)
{
    s->center = center;
    s->radius = radius;
    s->cdf[0] = 0.0;
    s->media_power = 0.0;
    for (int i = 0; i < scene->light_count; ++i) {
        double p = vbl_light_power(&scene->lights[i], center, radius);
        s->cdf[i + 1] = s->cdf[i] + (p > 0.0 && isfinite(p) ? p : 0.0);
    }
    return s->cdf[scene->light_count];
}

double vbl_photon_source_add_media(vbl_photon_source* s, const vbl_scene* scene)
{
    double p = vbl_media_emission_power(scene);
    s->media_power = p > 0.0 && isfinite(p) ? p : 0.0;
    return s->cdf[scene->light_count] + s->media_power;
}

double vbl_media_emission_power(const vbl_scene* scene)
{
    const vbl_emission_lights* el = &scene->emission_lights;
    if (!scene->has_emission || el->count == 0 || !el->point_cdf) return 0.0;
    return 4.0 * VBL_PI * el->point_cdf[el->count];
}

int vbl_media_sample_emission(const vbl_scene* scene, const vbl_extinction* extinction, vbl_extinction_cursor* cursor,
                              vbl_emission_cursor* emission, const double u[7], vbl_emission_sample* out)
{
    const vbl_emission_lights* el = &scene->emission_lights;
    vbl_vec3 x;
    double prob = 0.0;
    int b = vbl_emission_lights_pick_point(el, scene, u[0], u + 1, &x, &prob);
    if (b < 0 || !(prob > 0.0)) return 0;
    const vbl_emission_block* blk = &el->blocks[b];
    const int m = blk->medium;
    const vbl_medium* med = &scene->media[m];
    double comps[VBL_MAX_MEDIA] = {0};
    vbl_extinction_eval(extinction, cursor, x, comps);
    const double st = comps[m];
    if (!(st > 0.0)) return 0;
    vbl_vec3 le = vbl_medium_le(scene, emission, m, x);
    const vbl_vec3 a = med->albedo_volume[0] ? vbl_medium_albedo_at(scene, m, x, emission->time) : med->albedo;
    vbl_vec3 e = vbl_v3(st * (1.0 - a.x) * le.x, st * (1.0 - a.y) * le.y, st * (1.0 - a.z) * le.z);
    const double emax = vbl_v3_max_component(e);
    if (!(emax > 0.0)) return 0;
    double q = blk->bound > 0.0 ? fmin(1.0, emax / blk->bound) : 1.0;
    if (!(u[4] < q)) return 0;
    double pdf_dir = 0.0;
    out->origin = x;
    out->direction = vbl_sample_uniform_sphere(u[5], u[6], &pdf_dir);
    if (!(pdf_dir > 0.0)) return 0;
    /* e / (pdf_x pdf_dir q), pdf_x = prob / volume */
    out->flux = vbl_v3_scale(e, blk->volume / (prob * pdf_dir * q));
    return 1;
}

/* vbl_photon_emit with or without the media (cursors NULL: lights only). */
static int vbl_photon_emit_from(const vbl_photon_source* s, const vbl_scene* scene, const vbl_extinction* extinction,
                                vbl_extinction_cursor* cursor, vbl_emission_cursor* emission, size_t paths,
                                vbl_rng* rng, vbl_emission_sample* es, vbl_vec3* phi)
{
    const double lights = s->cdf[scene->light_count];
    const double media = emission ? s->media_power : 0.0;
    const double total = lights + media;
    double target = vbl_rng_uniform(rng) * total;
    double select_pdf = 0.0;
    if (media > 0.0 && !(target < lights)) {
        double u[7];
        for (int k = 0; k < 7; ++k) u[k] = vbl_rng_uniform(rng);
        if (!vbl_media_sample_emission(scene, extinction, cursor, emission, u, es)) return 0;
        select_pdf = media / total;
    } else {
        int pick = -1;
        for (int i = 0; i < scene->light_count; ++i)
            if (s->cdf[i + 1] > s->cdf[i]) {
                pick = i;
                if (target < s->cdf[i + 1]) break;
            }
        if (pick < 0) return 0;
        select_pdf = (s->cdf[pick + 1] - s->cdf[pick]) / total;
        double u[4];
        for (int k = 0; k < 4; ++k) u[k] = vbl_rng_uniform(rng);
        if (!vbl_light_sample_emission(&scene->lights[pick], s->center, s->radius, u, es)) return 0;
    }
    *phi = vbl_v3_scale(es->flux, 1.0 / (select_pdf * (double)paths));
    const double phi0 = vbl_v3_max_component(*phi);
    return phi0 > 0.0 && isfinite(phi0);
}

int vbl_photon_emit(const vbl_photon_source* s, const vbl_scene* scene, size_t paths, vbl_rng* rng,
                    vbl_emission_sample* es, vbl_vec3* phi)
{
    return vbl_photon_emit_from(s, scene, NULL, NULL, NULL, paths, rng, es, phi);
}

int vbl_photon_emit_with_media(const vbl_photon_source* s, const vbl_scene* scene, const vbl_extinction* extinction,
                               vbl_extinction_cursor* cursor, vbl_emission_cursor* emission, size_t paths,
                               vbl_rng* rng, vbl_emission_sample* es, vbl_vec3* phi)
{
    return vbl_photon_emit_from(s, scene, extinction, cursor, emission, paths, rng, es, phi);
}

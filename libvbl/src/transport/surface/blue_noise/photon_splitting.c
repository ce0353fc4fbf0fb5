/* Photon splitting into per-light incident fields, and their conversion to emission profiles
 * (photon_splitting.h; Li et al. 2022, section 3.3, eq. 3). */
#include "transport/surface/blue_noise/photon_splitting.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

vbl_vec3 vbl_bn_to_local(vbl_vec3 n, vbl_vec3 w)
{
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    return vbl_v3(vbl_v3_dot(w, t), vbl_v3_dot(w, b), vbl_v3_dot(w, n));
}

vbl_vec3 vbl_bn_to_world(vbl_vec3 n, vbl_vec3 w)
{
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    return vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, w.x), vbl_v3_scale(b, w.y)), vbl_v3_scale(n, w.z));
}

static int is_unit(vbl_vec3 v) { double l = vbl_v3_length(v); return isfinite(l) && fabs(l - 1.0) <= 1e-6; }

static size_t cells_of(const vbl_bn_light* l, int res) { return l->diffuse ? 1 : (size_t)res * (size_t)res; }

vbl_result vbl_bn_tree_set_light_radii(vbl_bn_kdtree* tree, const vbl_bn_light* lights, size_t count)
{
    double* radii = (double*)malloc((count ? count : 1) * sizeof(double));
    if (!radii) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise lights: cannot allocate %zu radii", count);
    for (size_t i = 0; i < count; ++i) radii[i] = lights[i].radius;
    vbl_result rc = vbl_bn_kdtree_set_radii(tree, radii);
    free(radii);
    return rc;
}

vbl_result vbl_bn_field_init(vbl_bn_incident_field* f, const vbl_bn_light* lights, size_t light_count, int res)
{
    memset(f, 0, sizeof *f);
    f->lights = lights;
    f->light_count = light_count;
    vbl_result rc = vbl_oct_table_init(&f->table, res);
    if (rc != VBL_SUCCESS) return rc;
    for (size_t i = 0; i < light_count; ++i) {
        const vbl_bn_light* l = &lights[i];
        if (!isfinite(l->position.x + l->position.y + l->position.z) || !is_unit(l->normal)) {
            vbl_bn_field_free(f);
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                             "photon splitting: lights[%zu]: position must be finite and normal a unit vector", i);
        }
        if (!(l->radius > 0.0) || !isfinite(l->radius)) {
            vbl_bn_field_free(f);
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "photon splitting: lights[%zu].radius = %g must be finite and > 0",
                             i, l->radius);
        }
        if (l->radius > f->max_radius) f->max_radius = l->radius;
    }
    f->offset = (size_t*)malloc((light_count + 1) * sizeof(size_t));
    f->positions = (vbl_vec3*)malloc((light_count ? light_count : 1) * sizeof(vbl_vec3));
    if (!f->offset || !f->positions) goto oom;
    f->offset[0] = 0;
    for (size_t i = 0; i < light_count; ++i) {
        f->offset[i + 1] = f->offset[i] + cells_of(&lights[i], res);
        f->positions[i] = lights[i].position;
    }
    f->values = (vbl_vec3*)calloc(f->offset[light_count] ? f->offset[light_count] : 1, sizeof(vbl_vec3));
    if (!f->values) goto oom;
    rc = vbl_bn_kdtree_build(&f->tree, f->positions, NULL, light_count);
    if (rc == VBL_SUCCESS) rc = vbl_bn_tree_set_light_radii(&f->tree, lights, light_count);
    if (rc != VBL_SUCCESS) {
        vbl_bn_field_free(f);
        return rc;
    }
    return VBL_SUCCESS;
oom:
    vbl_bn_field_free(f);
    return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "photon splitting: cannot allocate the fields of %zu lights", light_count);
}

void vbl_bn_field_free(vbl_bn_incident_field* f)
{
    vbl_oct_table_free(&f->table);
    vbl_bn_kdtree_free(&f->tree);
    free(f->offset);
    free(f->values);
    free(f->positions);
    f->offset = NULL;
    f->values = NULL;
    f->positions = NULL;
    f->light_count = 0;
}

typedef struct split_ctx {
    const vbl_bn_incident_field* f;
    const vbl_bn_photon_hit* hit;
    size_t* idx;
    double* w;
    size_t capacity, found;
    double sum;
} split_ctx;

static void split_visit(void* ctx, size_t i, double d2)
{
    split_ctx* c = (split_ctx*)ctx;
    const vbl_bn_light* l = &c->f->lights[i];
    double r2 = l->radius * l->radius;
    if (!(d2 < r2)) return;
    if (!(vbl_v3_dot(l->normal, c->hit->normal) > 0.0) || !(vbl_v3_dot(l->normal, c->hit->incident) > 0.0)) return;
    double w = 1.0 - d2 / r2; /* 1 - (d / r)^2, > 0 here */
    if (c->found < c->capacity) {
        c->idx[c->found] = i;
        c->w[c->found] = w;
    }
    ++c->found;
    c->sum += w;
}

size_t vbl_bn_split_weights(const vbl_bn_incident_field* f, const vbl_bn_photon_hit* hit, size_t* lights,
                            double* weights, size_t capacity)
{
    split_ctx c = {f, hit, lights, weights, capacity, 0, 0.0};
    vbl_bn_kdtree_within(&f->tree, hit->position, f->max_radius, split_visit, &c);
    size_t n = c.found < capacity ? c.found : capacity;
    for (size_t k = 0; k < n; ++k) weights[k] /= c.sum; /* sum >= each w > 0 */
    return c.found;
}

static void add_to_light(vbl_bn_incident_field* f, size_t i, vbl_vec3 incident, vbl_vec3 power)
{
    const vbl_bn_light* l = &f->lights[i];
    size_t slot = f->offset[i];
    if (!l->diffuse) slot += (size_t)vbl_oct_cell(vbl_bn_to_local(l->normal, incident), f->table.resolution);
    f->values[slot] = vbl_v3_add(f->values[slot], power);
}

vbl_result vbl_bn_split_photons(vbl_bn_incident_field* f, const vbl_bn_photon_hit* hits, size_t count)
{
    size_t capacity = 64;
    size_t* idx = (size_t*)malloc(capacity * sizeof(size_t));
    double* w = (double*)malloc(capacity * sizeof(double));
    vbl_result rc = VBL_SUCCESS;
    if (!idx || !w) {
        rc = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "photon splitting: cannot allocate the weight buffer");
        goto done;
    }
    for (size_t h = 0; h < count; ++h) {
        const vbl_bn_photon_hit* hit = &hits[h];
        vbl_vec3 p = hit->power;
        if (!(p.x >= 0.0 && p.y >= 0.0 && p.z >= 0.0 && isfinite(p.x + p.y + p.z))) {
            rc = vbl_error(VBL_ERROR_INVALID_ARGUMENT, "photon splitting: hits[%zu].power = (%g, %g, %g) is not finite and >= 0",
                           h, p.x, p.y, p.z);
            goto done;
        }
        if (!isfinite(hit->position.x + hit->position.y + hit->position.z) || !is_unit(hit->normal) ||
            !is_unit(hit->incident)) {
            rc = vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                           "photon splitting: hits[%zu]: position must be finite, normal and incident unit vectors", h);
            goto done;
        }
        size_t found = vbl_bn_split_weights(f, hit, idx, w, capacity);
        if (found > capacity) {
            size_t cap = 2 * found;
            size_t* ni = (size_t*)realloc(idx, cap * sizeof(size_t));
            if (ni) idx = ni;
            double* nw = (double*)realloc(w, cap * sizeof(double));
            if (nw) w = nw;
            if (!ni || !nw) {
                rc = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "photon splitting: cannot grow the weight buffer to %zu", cap);
                goto done;
            }
            capacity = cap;
            found = vbl_bn_split_weights(f, hit, idx, w, capacity);
        }
        f->split_power = vbl_v3_add(f->split_power, p);
        ++f->hits;
        if (found == 0) {
            f->lost_power = vbl_v3_add(f->lost_power, p);
            ++f->lost_hits;
            continue;
        }
        for (size_t k = 0; k < found; ++k) add_to_light(f, idx[k], hit->incident, vbl_v3_scale(p, w[k]));
    }
done:
    free(idx);
    free(w);
    return rc;
}

vbl_result vbl_bn_field_merge(vbl_bn_incident_field* dst, const vbl_bn_incident_field* src)
{
    if (dst->light_count != src->light_count || dst->table.resolution != src->table.resolution ||
        dst->offset[dst->light_count] != src->offset[src->light_count])
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "photon splitting: merging fields of different lights/resolution");
    for (size_t k = 0; k < dst->offset[dst->light_count]; ++k) dst->values[k] = vbl_v3_add(dst->values[k], src->values[k]);
    dst->split_power = vbl_v3_add(dst->split_power, src->split_power);
    dst->lost_power = vbl_v3_add(dst->lost_power, src->lost_power);
    dst->hits += src->hits;
    dst->lost_hits += src->lost_hits;
    return VBL_SUCCESS;
}

vbl_vec3 vbl_bn_field_stored_power(const vbl_bn_incident_field* f)
{
    vbl_vec3 s = vbl_v3(0, 0, 0);
    for (size_t k = 0; k < f->offset[f->light_count]; ++k) s = vbl_v3_add(s, f->values[k]);
    return s;
}

/* ---- emission -------------------------------------------------------------------------------- */

vbl_result vbl_bn_emission_from_field(const vbl_bn_incident_field* f, const vbl_material* materials,
                                      size_t material_count, vbl_bn_emission* e)
{
    memset(e, 0, sizeof *e);
    for (size_t i = 0; i < f->light_count; ++i)
        if (f->lights[i].material < 0 || (size_t)f->lights[i].material >= material_count)
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "photon splitting: lights[%zu].material = %d is outside [0, %zu)", i,
                             f->lights[i].material, material_count);
    const int res = f->table.resolution;
    const size_t cells = (size_t)res * (size_t)res;
    e->lights = f->lights;
    e->light_count = f->light_count;
    e->resolution = res;
    e->radiance = 0;
    e->offset = (size_t*)malloc((f->light_count + 1) * sizeof(size_t));
    e->values = (vbl_vec3*)calloc(f->offset[f->light_count] ? f->offset[f->light_count] : 1, sizeof(vbl_vec3));
    e->power = (vbl_vec3*)calloc(f->light_count ? f->light_count : 1, sizeof(vbl_vec3));
    if (!e->offset || !e->values || !e->power) {
        vbl_bn_emission_free(e);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "photon splitting: cannot allocate the emission of %zu lights",
                         f->light_count);
    }
    memcpy(e->offset, f->offset, (f->light_count + 1) * sizeof(size_t));
    const vbl_vec3 n_local = vbl_v3(0.0, 0.0, 1.0);
#pragma omp parallel for schedule(dynamic, 16)
    for (long long li = 0; li < (long long)f->light_count; ++li) {
        const size_t i = (size_t)li;
        const vbl_bn_light* l = &f->lights[i];
        const vbl_material* m = &materials[l->material];
        const vbl_vec3* in = f->values + f->offset[i];
        vbl_vec3* out = e->values + e->offset[i];
        if (l->diffuse) {
            /* Lambert: J = E albedo / pi, P = E albedo */
            out[0] = vbl_v3_scale(vbl_v3_mul(in[0], m->albedo), VBL_INV_PI);
            e->power[i] = vbl_v3_mul(in[0], m->albedo);
            continue;
        }
        /* f is evaluated in the local frame (normal = +z): the frame is a rotation */
        vbl_vec3 power = vbl_v3(0, 0, 0);
        for (size_t o = 0; o < cells; ++o) {
            if (!(f->table.upper[o] > 0.0)) continue; /* entirely below the surface: I = 0 */
            vbl_vec3 wo = f->table.direction[o];
            vbl_vec3 j = vbl_v3(0, 0, 0);
            for (size_t c = 0; c < cells; ++c) {
                if (!(in[c].x > 0.0 || in[c].y > 0.0 || in[c].z > 0.0)) continue;
                vbl_vec3 fr = vbl_material_eval(m, n_local, wo, f->table.direction[c]);
                j = vbl_v3_add(j, vbl_v3_mul(in[c], fr));
            }
            out[o] = j;
            power = vbl_v3_madd(power, j, wo.z * f->table.upper[o]);
        }
        e->power[i] = power;
    }
    return VBL_SUCCESS;
}

void vbl_bn_emission_free(vbl_bn_emission* e)
{
    free(e->offset);
    free(e->values);
    free(e->power);
    e->offset = NULL;
    e->values = NULL;
    e->power = NULL;
    e->light_count = 0;
}

vbl_vec3 vbl_bn_emission_intensity(const vbl_bn_emission* e, size_t light, vbl_vec3 omega)
{
    const vbl_bn_light* l = &e->lights[light];
    double c = vbl_v3_dot(l->normal, omega);
    if (!(c > 0.0)) return vbl_v3(0, 0, 0);
    size_t slot = e->offset[light];
    if (!l->diffuse) slot += (size_t)vbl_oct_cell(vbl_bn_to_local(l->normal, omega), e->resolution);
    return e->radiance ? e->values[slot] : vbl_v3_scale(e->values[slot], c);
}

/* Export of blue-noise virtual lights as surface VSL store entries (vsl_export.h). */
#include "transport/surface/blue_noise/vsl_export.h"

#include <stdio.h>
#include <stdlib.h>

#include "core/error.h"

static int nonzero(vbl_vec3 p) { return p.x > 0.0 || p.y > 0.0 || p.z > 0.0; }

vbl_result vbl_bn_export_vsls(const vbl_bn_incident_field* f, vbl_surface_vsl_store* store, size_t* added)
{
    size_t n = 0;
    const size_t cells = (size_t)f->table.resolution * (size_t)f->table.resolution;
    for (size_t i = 0; i < f->light_count; ++i) {
        const vbl_bn_light* l = &f->lights[i];
        const vbl_vec3* in = f->values + f->offset[i];
        vbl_surface_vsl v;
        v.position = l->position;
        v.normal = l->normal;
        v.material = l->material;
        v.bounce = 1;
        size_t entries = l->diffuse ? 1 : cells;
        for (size_t c = 0; c < entries; ++c) {
            if (!nonzero(in[c])) continue;
            v.incident = l->diffuse ? l->normal : vbl_v3_normalize(vbl_bn_to_world(l->normal, f->table.direction[c]));
            v.power = in[c];
            vbl_result rc = vbl_surface_vsl_store_add(store, &v);
            if (rc != VBL_SUCCESS) {
                if (added) *added = n;
                return rc;
            }
            ++n;
        }
    }
    if (added) *added = n;
    return VBL_SUCCESS;
}

vbl_result vbl_bn_split_surface_vsls(vbl_bn_incident_field* field, const vbl_surface_vsl* vsls, size_t count)
{
    enum { CHUNK = 1024 };
    vbl_bn_photon_hit hits[CHUNK];
    for (size_t start = 0; start < count; start += CHUNK) {
        size_t n = count - start < CHUNK ? count - start : CHUNK;
        for (size_t k = 0; k < n; ++k) {
            const vbl_surface_vsl* v = &vsls[start + k];
            hits[k].position = v->position;
            hits[k].normal = v->normal;
            hits[k].incident = v->incident;
            hits[k].power = v->power;
        }
        vbl_result rc = vbl_bn_split_photons(field, hits, n);
        if (rc != VBL_SUCCESS) {
            char why[512];
            snprintf(why, sizeof why, "%s", vbl_last_error_message()); /* names hits[k] of this chunk */
            return vbl_error(rc, "surface VSLs from vsls[%zu] on: %s", start, why);
        }
    }
    return VBL_SUCCESS;
}

static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

double vbl_bn_median_radius(const vbl_bn_light* lights, size_t count)
{
    if (count == 0) return 0.0;
    double* r = (double*)malloc(count * sizeof(double));
    if (!r) return lights[0].radius;
    for (size_t i = 0; i < count; ++i) r[i] = lights[i].radius;
    qsort(r, count, sizeof(double), cmp_double);
    double m = count % 2 ? r[count / 2] : 0.5 * (r[count / 2 - 1] + r[count / 2]);
    free(r);
    return m;
}

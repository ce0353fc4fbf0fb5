/* One-call virtual blue noise light preparation (prepare.h). */
#include "transport/surface/blue_noise/prepare.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

void vbl_bn_prepared_free(vbl_bn_prepared* p)
{
    vbl_bn_light_set_free(&p->set);
    vbl_bn_emission_free(&p->emission);
    vbl_bn_field_free(&p->field);
    free(p->lights);
    memset(p, 0, sizeof *p);
}

vbl_result vbl_bn_prepare(const vbl_scene* scene, const vbl_bn_prepare_options* options, vbl_bn_prepared* out)
{
    memset(out, 0, sizeof *out);
    vbl_bn_prepare_options defaults = VBL_BN_PREPARE_DEFAULT;
    const vbl_bn_prepare_options* o = options ? options : &defaults;
    if (o->size < sizeof(vbl_bn_prepare_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise prepare: options.size = %zu is too small", o->size);
    /* o->stop reaches every long step (issue #18: a signal ends the render within a second) */
    vbl_bn_placement_options placement = o->placement;
    vbl_bn_elimination_options elimination = o->elimination;
    vbl_bn_photon_options photons = o->photons;
    if (o->stop) {
        placement.stop = elimination.stop = photons.stop = o->stop;
        placement.stop_user = elimination.stop_user = photons.stop_user = o->stop_user;
    }
    vbl_bn_candidate* c = NULL;
    size_t nc = 0;
    vbl_result rc = vbl_bn_place_candidates(scene, &placement, &c, &nc, &out->placement);
    if (rc != VBL_SUCCESS) return rc;
    if (nc == 0) {
        free(c);
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "blue noise prepare: scene '%s': no camera sub-path reached a second surface", scene->path);
    }
    rc = vbl_bn_lights_from_candidates(c, nc, o->lights, o->alpha, scene->materials, (size_t)scene->surface_count,
                                       &elimination, &out->lights, &out->light_count);
    free(c);
    if (rc != VBL_SUCCESS) goto fail;
    rc = vbl_bn_field_init(&out->field, out->lights, out->light_count, o->resolution);
    if (rc != VBL_SUCCESS) goto fail;
    rc = vbl_bn_trace_photons(scene, &photons, &out->field, &out->photons);
    if (rc != VBL_SUCCESS) goto fail;
    rc = vbl_bn_emission_from_field(&out->field, scene->materials, (size_t)scene->surface_count, &out->emission);
    if (rc != VBL_SUCCESS) goto fail;
    rc = vbl_bn_light_set_init(&out->set, out->lights, out->light_count, out->emission.power, o->alpha);
    if (rc != VBL_SUCCESS) goto fail;
    return VBL_SUCCESS;
fail:
    vbl_bn_prepared_free(out);
    return rc;
}

vbl_result vbl_bn_prepared_to_radiance(vbl_bn_prepared* p)
{
    vbl_bn_emission* e = &p->emission;
    for (size_t j = 0; j < p->light_count; ++j) {
        double r = p->lights[j].radius;
        double s = r > 0.0 ? 1.0 / (VBL_PI * r * r) : 0.0; /* radius > 0 by construction */
        for (size_t k = e->offset[j]; k < e->offset[j + 1]; ++k) e->values[k] = vbl_v3_scale(e->values[k], s);
        e->power[j] = vbl_v3_scale(e->power[j], s);
    }
    e->radiance = 1;
    double alpha = p->set.alpha;
    vbl_bn_light_set_free(&p->set);
    return vbl_bn_light_set_init(&p->set, p->lights, p->light_count, e->power, alpha);
}

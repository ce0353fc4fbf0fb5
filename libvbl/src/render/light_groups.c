/* Light groups (options.light_groups; docs/readme/output.md, "Light groups"): the scene is
 * rendered once per group with only that group's lights (and, for "default", the emissive media),
 * with the method asked for, so every method splits by group and its virtual lights carry the
 * group of the light they came from by construction. The film's class layers are the float sums of
 * the groups' class layers (group order), the beauty is the float sum of those classes as always,
 * and each group's beauty is written as the layer "lightgroup_<name>". Group g renders with the
 * seed seed + g * 0x9E3779B97F4A7C15 (g = 0: the seed itself), so the groups' noise is independent
 * and their variances add. A group without lights (the default group when every light is
 * tagged and no medium emits) is not rendered and has no layer. The camera-ray AOVs (A, Z,
 * samples) are the first rendered group's. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "film/film.h"
#include "render/render_internal.h"

#define VBL_LIGHT_GROUP_SEED_STEP 0x9E3779B97F4A7C15ull

/* `scene` with only the lights of group g (and the media's emission only in group 0). */
static vbl_scene* vbl_light_group_scene(const vbl_scene* scene, int g)
{
    vbl_scene* part = malloc(sizeof *part);
    if (!part) return NULL;
    *part = *scene; /* shares volumes, surfaces and emission tables read-only; freed with free() */
    part->light_count = 0;
    part->has_delta_lights = part->has_visible_lights = 0;
    for (int i = 0; i < scene->light_count; ++i) {
        const vbl_light* l = &scene->lights[i];
        if (l->group != g) continue;
        part->lights[part->light_count++] = *l;
        if (vbl_v3_max_component(l->color) <= 0.0) continue; /* as the loader counts them */
        if (l->type == VBL_LIGHT_QUAD || l->type == VBL_LIGHT_ENVIRONMENT) part->has_visible_lights = 1;
        else part->has_delta_lights = 1;
    }
    if (g != 0) part->has_emission = 0;
    return part;
}

static const float* vbl_group_layer(const vbl_film* film, const char* name, int channels)
{
    int c = 0;
    const float* px = vbl_film_layer(film, name, &c);
    return px && c == channels ? px : NULL;
}

/* The combined film of the groups' films. */
static vbl_result vbl_light_groups_combine(const vbl_scene* scene, const vbl_render_options* options,
                                           vbl_film* const* films, const int* groups, int count, vbl_film** out_film)
{
    const int w = scene->camera.width, h = scene->camera.height;
    const size_t n = (size_t)w * (size_t)h;
    vbl_film_layout layout;
    vbl_film_layout_for(scene, options, &layout);
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(films[0], &stats);
    stats.seed = options->seed;
    for (int g = 1; g < count; ++g) {
        vbl_film_stats s;
        memset(&s, 0, sizeof s);
        s.size = sizeof s;
        vbl_film_get_stats(films[g], &s);
        stats.render_seconds += s.render_seconds;
    }
    vbl_film* film = NULL;
    vbl_result r = vbl_film_create(w, h, &stats, &film);
    float* buf = r ? NULL : malloc(sizeof(float) * 4 * (n ? n : 1));
    float* beauty = r ? NULL : calloc(4 * (n ? n : 1), sizeof(float));
    if (!r && (!buf || !beauty)) r = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "render: out of memory for the light groups");
    /* classes: sums over the groups, in group order; the beauty: their sum in class order */
    float* classes[VBL_CLASS_COUNT] = {NULL};
    for (int c = 0; !r && c < VBL_CLASS_COUNT; ++c) {
        if (!layout.transport[c]) continue;
        classes[c] = calloc(3 * (n ? n : 1), sizeof(float));
        if (!classes[c]) {
            r = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "render: out of memory for the light groups");
            break;
        }
        for (int g = 0; g < count; ++g) {
            const float* px = vbl_group_layer(films[g], vbl_transport_class_name((vbl_transport_class)c), 3);
            if (px)
                for (size_t v = 0; v < 3 * n; ++v) classes[c][v] += px[v];
        }
    }
    const float* alpha = r ? NULL : vbl_group_layer(films[0], "", 4);
    for (size_t i = 0; !r && i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            float sum = 0.0f;
            for (int c = 0; c < VBL_CLASS_COUNT; ++c)
                if (classes[c] && vbl_film_class_in_beauty(c, layout.transparent)) sum += classes[c][3 * i + k];
            beauty[4 * i + k] = sum;
        }
        beauty[4 * i + 3] = layout.opaque_alpha ? 1.0f : (alpha ? alpha[4 * i + 3] : 0.0f);
    }
    if (!r) r = vbl_film_add_layer(film, "", 4, NULL, beauty);
    for (int c = 0; !r && c < VBL_CLASS_COUNT; ++c)
        if (classes[c]) r = vbl_film_add_layer(film, vbl_transport_class_name((vbl_transport_class)c), 3, NULL, classes[c]);
    /* AOVs of the camera rays: group 0's (the same estimates in every group up to the seed) */
    static const char* const aovs[2] = {"Z", "samples"};
    for (int a = 0; !r && a < 2; ++a) {
        const float* px = vbl_group_layer(films[0], aovs[a], 1);
        if (px) r = vbl_film_add_layer(film, aovs[a], 1, NULL, px);
    }
    /* the variance of a sum of independent renders: the sum of their variances */
    if (!r && vbl_group_layer(films[0], "variance", 3)) {
        memset(buf, 0, sizeof(float) * 3 * n);
        for (int g = 0; g < count; ++g) {
            const float* px = vbl_group_layer(films[g], "variance", 3);
            if (px)
                for (size_t v = 0; v < 3 * n; ++v) buf[v] += px[v];
        }
        r = vbl_film_add_layer(film, "variance", 3, NULL, buf);
    }
    for (int g = 0; !r && g < count; ++g) {
        const float* px = vbl_group_layer(films[g], "", 4);
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) buf[3 * i + k] = px ? px[4 * i + k] : 0.0f;
        char name[32];
        snprintf(name, sizeof name, "lightgroup_%s", scene->light_groups[groups[g]]);
        r = vbl_film_add_layer(film, name, 3, NULL, buf);
    }
    if (!r) r = vbl_film_compute_totals(film);
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) free(classes[c]);
    free(buf);
    free(beauty);
    if (r) {
        vbl_film_release(film);
        return r;
    }
    *out_film = film;
    return VBL_SUCCESS;
}

vbl_result vbl_render_light_groups(const vbl_scene* scene, const vbl_render_options* options,
                                   const vbl_estimator* est, vbl_film** out_film)
{
    *out_film = NULL;
    if (options->time_limit > 0.0)
        return vbl_error(VBL_ERROR_UNSUPPORTED,
                         "%s: light_groups with a time_limit: the groups would end with different pass counts",
                         scene->path);
    vbl_film* films[VBL_MAX_LIGHT_GROUPS] = {NULL};
    int groups[VBL_MAX_LIGHT_GROUPS], count = 0;
    vbl_result r = VBL_SUCCESS;
    for (int g = 0; g < scene->light_group_count && !r; ++g) {
        int used = g == 0 && scene->has_emission; /* a group without lights gets no render and no layer */
        for (int i = 0; i < scene->light_count; ++i) used |= scene->lights[i].group == g;
        if (!used) continue;
        vbl_scene* part = vbl_light_group_scene(scene, g);
        if (!part) {
            r = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for the light groups", scene->path);
            break;
        }
        vbl_render_options o = *options;
        o.light_groups = 0;
        if (o.hybrid == VBL_HYBRID_AUTO) o.hybrid = VBL_HYBRID_OFF; /* auto renders as off with light groups */
        o.callback = NULL; /* passes of one group are not the render's progress */
        o.seed = options->seed + (uint64_t)g * VBL_LIGHT_GROUP_SEED_STEP;
        groups[count] = g;
        r = vbl_render_with_estimator(part, &o, est, &films[count++]);
        free(part);
    }
    if (!r) r = vbl_light_groups_combine(scene, options, films, groups, count, out_film);
    for (int g = 0; g < count; ++g) vbl_film_release(films[g]);
    return r;
}

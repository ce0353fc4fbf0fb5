/* Film layers: accumulators -> float layers; the public vbl_film getters. */
#include "render/film.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

static const char* const vbl_class_layer_names[VBL_CLASS_COUNT] = {
    "emission",          "surface_direct",      "volume_direct",     "surface_from_surface",
    "surface_from_volume", "volume_from_surface", "volume_from_volume", "volume_emission"};

void vbl_film_layout_for(const vbl_scene* scene, const vbl_render_options* options, vbl_film_layout* layout)
{
    memset(layout, 0, sizeof *layout);
    int lit_media = scene->media_count > 0 && (scene->light_count > 0 || scene->has_emission);
    layout->transport[VBL_CLASS_EMISSION] = scene->has_visible_lights;
    layout->transport[VBL_CLASS_VOLUME_DIRECT] = lit_media && options->max_bounces != 0;
    layout->transport[VBL_CLASS_VOLUME_FROM_VOLUME] =
        lit_media && (options->max_bounces < 0 || options->max_bounces >= 2);
    /* surface classes (scattering events: surface_direct 1, the *_from_* classes at least 2) */
    int lit_surfaces = scene->has_surfaces && (scene->light_count > 0 || scene->has_emission);
    int two = options->max_bounces < 0 || options->max_bounces >= 2;
    layout->transport[VBL_CLASS_SURFACE_DIRECT] = lit_surfaces && options->max_bounces != 0;
    layout->transport[VBL_CLASS_SURFACE_FROM_SURFACE] = lit_surfaces && two;
    layout->transport[VBL_CLASS_SURFACE_FROM_VOLUME] = lit_surfaces && two;
    layout->transport[VBL_CLASS_VOLUME_FROM_SURFACE] = lit_surfaces && scene->media_count > 0 && two;
    layout->transport[VBL_CLASS_VOLUME_EMISSION] = scene->has_emission;
    layout->depth = scene->media_count > 0 || scene->has_surfaces;
}

static vbl_film_layer_data* vbl_film_add_layer(vbl_film* film, const char* name, int channels,
                                               const char* const* channel_names)
{
    vbl_film_layer_data* layer = &film->layers[film->layer_count];
    size_t count = (size_t)film->width * (size_t)film->height * (size_t)channels;
    layer->pixels = calloc(count ? count : 1, sizeof(float));
    if (!layer->pixels) return NULL;
    snprintf(layer->name, sizeof layer->name, "%s", name);
    layer->channels = channels;
    for (int c = 0; c < channels; ++c) layer->channel_names[c] = channel_names[c];
    film->layer_count++;
    return layer;
}

vbl_result vbl_film_build(const vbl_pixel_accum* accum, int width, int height, const vbl_film_layout* layout,
                          const vbl_film_stats* stats, vbl_film** out_film)
{
    static const char* const rgba[4] = {"R", "G", "B", "A"};
    static const char* const z[1] = {"Z"};
    static const char* const y[1] = {"Y"};
    vbl_film* film = calloc(1, sizeof *film);
    if (!film) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "render: out of memory for the film");
    film->refcount = 1;
    film->width = width;
    film->height = height;
    film->stats = *stats;
    vbl_film_layer_data* beauty = vbl_film_add_layer(film, "", 4, rgba);
    vbl_film_layer_data* classes[VBL_CLASS_COUNT] = {NULL};
    int ok = beauty != NULL;
    for (int c = 0; ok && c < VBL_CLASS_COUNT; ++c)
        if (layout->transport[c]) ok = (classes[c] = vbl_film_add_layer(film, vbl_class_layer_names[c], 3, rgba)) != NULL;
    vbl_film_layer_data* depth = NULL;
    if (ok && layout->depth) ok = (depth = vbl_film_add_layer(film, "Z", 1, z)) != NULL;
    vbl_film_layer_data* samples = ok ? vbl_film_add_layer(film, "samples", 1, y) : NULL;
    vbl_film_layer_data* variance = samples ? vbl_film_add_layer(film, "variance", 3, rgba) : NULL;
    if (!variance) {
        vbl_film_release(film);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "render: out of memory for the film");
    }
    size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; ++i) {
        const vbl_pixel_accum* a = &accum[i];
        double inv = a->samples > 0.0 ? 1.0 / a->samples : 0.0;
        float sum[3] = {0.0f, 0.0f, 0.0f};
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            if (!classes[c]) continue;
            for (int k = 0; k < 3; ++k) {
                float v = (float)(a->L[c][k] * inv);
                classes[c]->pixels[3 * i + k] = v;
                sum[k] += v;
            }
        }
        for (int k = 0; k < 3; ++k) beauty->pixels[4 * i + k] = sum[k];
        beauty->pixels[4 * i + 3] = (float)(a->alpha * inv);
        if (depth) depth->pixels[i] = a->depth_hits > 0.0 ? (float)(a->depth / a->depth_hits) : 0.0f;
        samples->pixels[i] = (float)a->samples;
        for (int k = 0; k < 3; ++k) {
            double var = 0.0;
            if (a->var_n > 1.0) {
                double mean = a->var_sum[k] / a->var_n;
                double s2 = (a->var_sq[k] - mean * a->var_sum[k]) / (a->var_n - 1.0);
                var = s2 > 0.0 ? s2 / a->var_n : 0.0;
            }
            variance->pixels[3 * i + k] = (float)var;
        }
    }
    *out_film = film;
    return VBL_SUCCESS;
}

void vbl_film_retain(vbl_film* film)
{
    if (film) __atomic_add_fetch(&film->refcount, 1, __ATOMIC_RELAXED);
}

void vbl_film_release(vbl_film* film)
{
    if (!film || __atomic_sub_fetch(&film->refcount, 1, __ATOMIC_ACQ_REL) != 0) return;
    for (int i = 0; i < film->layer_count; ++i) free(film->layers[i].pixels);
    free(film);
}

int vbl_film_width(const vbl_film* film) { return film ? film->width : 0; }
int vbl_film_height(const vbl_film* film) { return film ? film->height : 0; }
int vbl_film_layer_count(const vbl_film* film) { return film ? film->layer_count : 0; }

const char* vbl_film_layer_name(const vbl_film* film, int index)
{
    if (!film || index < 0 || index >= film->layer_count) return NULL;
    return film->layers[index].name;
}

static const vbl_film_layer_data* vbl_film_find(const vbl_film* film, const char* name)
{
    if (!film || !name) return NULL;
    for (int i = 0; i < film->layer_count; ++i)
        if (!strcmp(film->layers[i].name, name)) return &film->layers[i];
    return NULL;
}

int vbl_film_layer_channel_count(const vbl_film* film, const char* name)
{
    const vbl_film_layer_data* layer = vbl_film_find(film, name);
    return layer ? layer->channels : 0;
}

const char* vbl_film_layer_channel_name(const vbl_film* film, const char* name, int channel)
{
    const vbl_film_layer_data* layer = vbl_film_find(film, name);
    if (!layer || channel < 0 || channel >= layer->channels) return NULL;
    return layer->channel_names[channel];
}

const float* vbl_film_layer(const vbl_film* film, const char* name, int* channels)
{
    const vbl_film_layer_data* layer = vbl_film_find(film, name);
    if (channels) *channels = layer ? layer->channels : 0;
    return layer ? layer->pixels : NULL;
}

const float* vbl_film_layer_rgb(const vbl_film* film, const char* name)
{
    const vbl_film_layer_data* layer = vbl_film_find(film, name);
    return layer && layer->channels == 3 ? layer->pixels : NULL;
}

vbl_result vbl_film_get_stats(const vbl_film* film, vbl_film_stats* out)
{
    if (!film || !out) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_get_stats: NULL argument");
    if (out->size < sizeof(vbl_film_stats))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_get_stats: out.size is too small");
    size_t size = out->size;
    *out = film->stats;
    out->size = size;
    return VBL_SUCCESS;
}

/* Film layers: accumulators -> float layers; the public vbl_film getters. */
#include "film/film.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* The one list of layer names (vbl/vbl_film.h): the film, the EXR files, vbl merge and Python use it. */
static const char* const vbl_class_layer_names[VBL_CLASS_COUNT] = {
    "background",        "surface_direct",      "volume_direct",     "surface_from_surface",
    "surface_from_volume", "volume_from_surface", "volume_from_volume", "volume_emission"};

const char* vbl_transport_class_name(vbl_transport_class transport_class)
{
    return (unsigned)transport_class < (unsigned)VBL_CLASS_COUNT ? vbl_class_layer_names[transport_class] : NULL;
}

vbl_result vbl_transport_class_parse(const char* name, vbl_transport_class* out)
{
    for (int c = 0; name && c < VBL_CLASS_COUNT; ++c)
        if (!strcmp(name, vbl_class_layer_names[c])) {
            if (out) *out = (vbl_transport_class)c;
            return VBL_SUCCESS;
        }
    return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                     "'%s' is not a transport class (background, surface_direct, volume_direct, surface_from_surface, "
                     "surface_from_volume, volume_from_surface, volume_from_volume, volume_emission)",
                     name ? name : "");
}

void vbl_film_layout_for(const vbl_scene* scene, const vbl_render_options* options, vbl_film_layout* layout)
{
    memset(layout, 0, sizeof *layout);
    int lit_media = scene->media_count > 0 && (scene->light_count > 0 || scene->has_emission);
    layout->transport[VBL_CLASS_BACKGROUND] = scene->has_visible_lights;
    layout->transparent = options->transparent != 0;
    layout->opaque_alpha = scene->has_visible_lights && !options->transparent;
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

static vbl_film_layer_data* vbl_film_alloc_layer(vbl_film* film, const char* name, int channels,
                                                 const char* const* channel_names)
{
    vbl_film_layer_data* layer = &film->layers[film->layer_count];
    size_t count = (size_t)film->width * (size_t)film->height * (size_t)channels;
    layer->pixels = calloc(count ? count : 1, sizeof(float));
    if (!layer->pixels) return NULL;
    snprintf(layer->name, sizeof layer->name, "%s", name);
    layer->channels = channels;
    for (int c = 0; c < channels; ++c) {
        snprintf(layer->channel_storage[c], sizeof layer->channel_storage[c], "%s", channel_names[c]);
        layer->channel_names[c] = layer->channel_storage[c];
    }
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
    vbl_film_layer_data* beauty = vbl_film_alloc_layer(film, "", 4, rgba);
    vbl_film_layer_data* classes[VBL_CLASS_COUNT] = {NULL};
    int ok = beauty != NULL;
    for (int c = 0; ok && c < VBL_CLASS_COUNT; ++c)
        if (layout->transport[c]) ok = (classes[c] = vbl_film_alloc_layer(film, vbl_class_layer_names[c], 3, rgba)) != NULL;
    vbl_film_layer_data* depth = NULL;
    if (ok && layout->depth) ok = (depth = vbl_film_alloc_layer(film, "Z", 1, z)) != NULL;
    vbl_film_layer_data* samples = ok ? vbl_film_alloc_layer(film, "samples", 1, y) : NULL;
    vbl_film_layer_data* variance = samples ? vbl_film_alloc_layer(film, "variance", 3, rgba) : NULL;
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
            const int in_beauty = vbl_film_class_in_beauty(c, layout->transparent);
            for (int k = 0; k < 3; ++k) {
                float v = (float)(a->L[c][k] * inv);
                classes[c]->pixels[3 * i + k] = v;
                if (in_beauty) sum[k] += v;
            }
        }
        for (int k = 0; k < 3; ++k) beauty->pixels[4 * i + k] = sum[k];
        beauty->pixels[4 * i + 3] = layout->opaque_alpha ? 1.0f : (float)(a->alpha * inv);
        if (depth) depth->pixels[i] = a->depth_hits > 0.0 ? (float)(a->depth / a->depth_hits) : VBL_FILM_Z_MISS;
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
    vbl_result r = vbl_film_compute_totals(film);
    if (r) {
        vbl_film_release(film);
        return r;
    }
    *out_film = film;
    return VBL_SUCCESS;
}

/* ---- totals ---------------------------------------------------------------------------- */

const char* vbl_film_total_name(int total)
{
    return total == 0 ? VBL_FILM_TOTAL_VOLUME_INDIRECT : (total == 1 ? VBL_FILM_TOTAL_SURFACE_INDIRECT : NULL);
}

int vbl_film_total_has_class(int total, int c)
{
    if (total == 0) return c == VBL_CLASS_VOLUME_FROM_SURFACE || c == VBL_CLASS_VOLUME_FROM_VOLUME;
    if (total == 1) return c == VBL_CLASS_SURFACE_FROM_SURFACE || c == VBL_CLASS_SURFACE_FROM_VOLUME;
    return 0;
}

static vbl_film_layer_data* vbl_film_find_mutable(vbl_film* film, const char* name)
{
    for (int i = 0; i < film->layer_count; ++i)
        if (!strcmp(film->layers[i].name, name)) return &film->layers[i];
    return NULL;
}

vbl_result vbl_film_compute_totals(vbl_film* film)
{
    static const char* const rgb[3] = {"R", "G", "B"};
    const size_t n = (size_t)film->width * (size_t)film->height;
    for (int t = 0; t < VBL_FILM_TOTAL_COUNT; ++t) {
        const vbl_film_layer_data* members[VBL_CLASS_COUNT];
        int count = 0;
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            if (!vbl_film_total_has_class(t, c)) continue;
            vbl_film_layer_data* l = vbl_film_find_mutable(film, vbl_class_layer_names[c]);
            if (l && l->channels == 3) members[count++] = l;
        }
        vbl_film_layer_data* total = vbl_film_find_mutable(film, vbl_film_total_name(t));
        if (!count) continue;
        if (!total) {
            if (film->layer_count >= VBL_FILM_MAX_LAYERS)
                return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "film: more than %d layers", VBL_FILM_MAX_LAYERS);
            total = vbl_film_alloc_layer(film, vbl_film_total_name(t), 3, rgb);
            if (!total) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "film: out of memory for the totals");
        }
        if (total->channels != 3) continue;
        for (size_t i = 0; i < 3 * n; ++i) {
            float sum = 0.0f;
            for (int m = 0; m < count; ++m) sum += members[m]->pixels[i];
            total->pixels[i] = sum;
        }
    }
    return VBL_SUCCESS;
}

vbl_result vbl_film_create(int width, int height, const vbl_film_stats* stats, vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    if (!stats || !out_film) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_create: NULL argument");
    if (width < 1 || height < 1 || (double)width * (double)height > 1e9)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_create: %dx%d is not a film size", width, height);
    if (stats->size < sizeof(vbl_film_stats) || stats->passes < 1 || stats->first_pass < 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "vbl_film_create: stats need size, passes >= 1 and first_pass >= 0 (passes = %d, first_pass = %d)",
                         stats->passes, stats->first_pass);
    vbl_film* film = calloc(1, sizeof *film);
    if (!film) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_film_create: out of memory");
    film->refcount = 1;
    film->width = width;
    film->height = height;
    film->stats = *stats;
    film->stats.size = sizeof film->stats;
    *out_film = film;
    return VBL_SUCCESS;
}

vbl_result vbl_film_add_layer(vbl_film* film, const char* name, int channels, const char* const* channel_names,
                              const float* pixels)
{
    static const char* const rgba[4] = {"R", "G", "B", "A"};
    static const char* const y[1] = {"Y"};
    static const char* const z[1] = {"Z"};
    if (!film || !name || !pixels) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: NULL argument");
    if (__atomic_load_n(&film->refcount, __ATOMIC_ACQUIRE) != 1)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: the film is shared (retained)");
    if (channels < 1 || channels > 4)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: layer '%s' has %d channels (1 to 4)", name,
                         channels);
    if (strlen(name) >= sizeof film->layers[0].name)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: layer name '%s' is too long", name);
    for (int i = 0; i < film->layer_count; ++i)
        if (!strcmp(film->layers[i].name, name))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: the film has a layer '%s' already", name);
    if (film->layer_count >= VBL_FILM_MAX_LAYERS)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: more than %d layers", VBL_FILM_MAX_LAYERS);
    if (!channel_names) channel_names = channels == 1 ? (!strcmp(name, "Z") ? z : y) : rgba;
    for (int c = 0; c < channels; ++c)
        if (!channel_names[c] || strlen(channel_names[c]) >= sizeof film->layers[0].channel_storage[0])
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_add_layer: layer '%s': bad channel name", name);
    vbl_film_layer_data* layer = vbl_film_alloc_layer(film, name, channels, channel_names);
    if (!layer) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_film_add_layer: out of memory");
    memcpy(layer->pixels, pixels, sizeof(float) * (size_t)film->width * (size_t)film->height * (size_t)channels);
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
    /* callers built before `transparent` pass the older, smaller struct: they get its fields */
    if (out->size < offsetof(vbl_film_stats, transparent))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_get_stats: out.size is too small");
    size_t size = out->size < sizeof(vbl_film_stats) ? out->size : sizeof(vbl_film_stats);
    vbl_film_stats copy = film->stats;
    copy.size = size;
    memcpy(out, &copy, size);
    return VBL_SUCCESS;
}

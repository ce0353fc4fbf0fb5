/* A film as the EXR `vbl render` writes (vbl_python_native.h): the same layers (AOVs by request,
 * Z unprefixed, one-channel layers as ".Y"), HALF rules and header attributes as
 * plugins/cli/render_output.c (vbl_render_meta_make); tests/pipeline/test_python_idioms.py compares the
 * two files attribute by attribute, so a change on one side fails there. */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "py_exr_convert.h"
#include "vbl_color.h"
#include "vbl_exr.h"
#include "vbl_python_native.h"

#define VBL_PY_MAX_LAYERS 16
#define VBL_PY_MAX_ATTRS 32

/* FNV-1a 64 of the scene file's bytes, as vbl:scene_hash. */
static vbl_result vbl_py_hash_file(const char* path, char out[40])
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return vbl_report_error(errno == ENOENT ? VBL_ERROR_FILE_NOT_FOUND : VBL_ERROR_FILE_IO,
                                "%s: cannot open the scene file (%s)", path, strerror(errno));
    uint64_t h = 0xcbf29ce484222325ull;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        for (size_t i = 0; i < n; ++i) h = (h ^ buf[i]) * 0x100000001b3ull;
    int bad = ferror(f);
    fclose(f);
    if (bad) return vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot read the scene file", path);
    snprintf(out, 40, "fnv1a64:%016llx", (unsigned long long)h);
    return VBL_SUCCESS;
}

static void vbl_py_media(const vbl_scene* scene, char* out, size_t size)
{
    size_t used = 0;
    out[0] = 0;
    for (int i = 0; i < vbl_scene_medium_count(scene); ++i) {
        const char* path = vbl_scene_medium_path(scene, i);
        char* real = path ? realpath(path, NULL) : NULL;
        int n = snprintf(out + used, size - used, "%s%s", i ? ";" : "", real ? real : (path ? path : ""));
        free(real);
        if (n < 0 || (size_t)n >= size - used) break;
        used += (size_t)n;
    }
}

static int vbl_py_list_has(const char* list, const char* name)
{
    size_t len = strlen(name);
    for (const char* p = list; p && *p;) {
        size_t n = strcspn(p, ",");
        if (n == len && !strncmp(p, name, n)) return 1;
        p += n;
        if (*p == ',') ++p;
    }
    return 0;
}

typedef enum { VBL_PY_BEAUTY, VBL_PY_TRANSPORT, VBL_PY_Z, VBL_PY_SAMPLES, VBL_PY_VARIANCE } vbl_py_kind;

static vbl_py_kind vbl_py_layer_kind(const char* name)
{
    if (!name[0]) return VBL_PY_BEAUTY;
    if (!strcmp(name, "Z")) return VBL_PY_Z;
    if (!strcmp(name, "samples")) return VBL_PY_SAMPLES;
    if (!strcmp(name, "variance")) return VBL_PY_VARIANCE;
    return VBL_PY_TRANSPORT;
}

typedef struct vbl_py_meta {
    char software[64], seed[32], options_hash[40], scene_hash[40], media[4096];
    vbl_exr_attribute attrs[VBL_PY_MAX_ATTRS];
    int count;
} vbl_py_meta;

static void vbl_py_meta_add(vbl_py_meta* m, const char* name, const char* value, vbl_exr_attribute_type type,
                            int int_value, double double_value)
{
    if (m->count >= VBL_PY_MAX_ATTRS) return;
    vbl_exr_attribute* a = &m->attrs[m->count++];
    a->name = name;
    a->value = value;
    a->type = type;
    a->int_value = int_value;
    a->double_value = double_value;
}

vbl_result vbl_py_film_write_exr(const vbl_film* film, const char* path, const vbl_py_exr_options* o)
{
    if (!film || !path || !o || o->size < sizeof *o || !o->scene || !o->render_options)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                "vbl_py_film_write_exr: film, path, options, options->scene and "
                                "options->render_options are required");
    const vbl_render_options* ro = o->render_options;
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_result r = vbl_film_get_stats(film, &stats);
    if (r) return r;
    vbl_py_meta* m = calloc(1, sizeof *m);
    if (!m) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    const char* scene_path = vbl_scene_path(o->scene);
    r = vbl_py_hash_file(scene_path, m->scene_hash);
    vbl_py_color* own = NULL;
    const vbl_py_color* color = o->color;
    if (!r && !color) r = vbl_py_color_open(NULL, &own), color = own;
    if (r) {
        free(m);
        return r;
    }
    const char* space = vbl_py_color_scene_space(color);
    const char* output = space; /* the EXR's colour space */
    double matrix[9];
    if (o->output_space) {
        r = vbl_color_resolve_space(vbl_py_color_config(color), o->output_space, &output);
        if (!r && strcmp(output, space)) r = vbl_py_color_matrix(color, output, matrix);
        if (r) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
            vbl_py_color_release(own);
            free(m);
            return vbl_report_error(r, "%s: output_space: %s", path, msg);
        }
    }
    const int convert = strcmp(output, space) != 0;
    const size_t n = (size_t)vbl_film_width(film) * (size_t)vbl_film_height(film);
    float* owned[VBL_PY_MAX_LAYERS] = {0};
    /* header attributes, in the CLI's order */
    const vbl_exr_attribute_type S = VBL_EXR_ATTRIBUTE_STRING, I = VBL_EXR_ATTRIBUTE_INT, D = VBL_EXR_ATTRIBUTE_DOUBLE;
    const char* status = o->status ? o->status
                                   : (stats.time_limited ? "time_limit" : (stats.cancelled ? "interrupted" : "complete"));
    snprintf(m->software, sizeof m->software, "vbl %s", vbl_version_string());
    snprintf(m->seed, sizeof m->seed, "%llu", (unsigned long long)stats.seed);
    vbl_render_options_hash(ro, m->options_hash, sizeof m->options_hash);
    vbl_py_media(o->scene, m->media, sizeof m->media);
    vbl_py_meta_add(m, "software", m->software, S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:version", vbl_version_string(), S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:scene", o->scene_label ? o->scene_label : scene_path, S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:scene_hash", m->scene_hash, S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:media", m->media, S, 0, 0.0);
    if (o->has_frame) vbl_py_meta_add(m, "vbl:frame", NULL, I, o->frame, 0.0);
    vbl_py_meta_add(m, "vbl:method", vbl_render_method_name(stats.method), S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:preset", o->preset ? o->preset : "none", S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:status", status, S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:passes", NULL, I, stats.passes, 0.0);
    vbl_py_meta_add(m, "vbl:passes_requested", NULL, I, o->passes_requested > 0 ? o->passes_requested : ro->passes, 0.0);
    vbl_py_meta_add(m, "vbl:first_pass", NULL, I, stats.first_pass, 0.0);
    vbl_py_meta_add(m, "vbl:spp", NULL, I, stats.spp, 0.0);
    vbl_py_meta_add(m, "vbl:light_paths", NULL, I, stats.light_paths, 0.0);
    vbl_py_meta_add(m, "vbl:seed", m->seed, S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:options_hash", m->options_hash, S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:threads", NULL, I, stats.threads, 0.0);
    vbl_py_meta_add(m, "vbl:max_bounces", NULL, I, ro->max_bounces, 0.0);
    vbl_py_meta_add(m, "vbl:transmittance", vbl_transmittance_estimator_name(ro->transmittance), S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:render_seconds", NULL, D, 0, stats.render_seconds);
    vbl_py_meta_add(m, "vbl:alpha", "premultiplied; A = 1 - transmittance along the camera ray", S, 0, 0.0);
    vbl_py_meta_add(m, "vbl:scene_color_space", space ? space : "scene_linear", S, 0, 0.0);
    /* layers as the CLI writes them */
    static const char* const z_names[1] = {"Z"};
    static const char* const y_names[1] = {"Y"};
    vbl_exr_layer layers[VBL_PY_MAX_LAYERS];
    vbl_py_kind kinds[VBL_PY_MAX_LAYERS];
    int count = 0;
    for (int i = 0; i < vbl_film_layer_count(film) && count < VBL_PY_MAX_LAYERS; ++i) {
        const char* name = vbl_film_layer_name(film, i);
        vbl_py_kind kind = vbl_py_layer_kind(name);
        if ((kind == VBL_PY_Z && !o->aov_z) || (kind == VBL_PY_SAMPLES && !o->aov_samples) ||
            (kind == VBL_PY_VARIANCE && !o->aov_variance))
            continue;
        int channels = 0;
        const float* px = vbl_film_layer(film, name, &channels);
        if (!px) continue;
        vbl_exr_layer* l = &layers[count++];
        memset(l, 0, sizeof *l);
        l->name = kind == VBL_PY_Z ? "" : name;
        l->channel_count = channels;
        l->channel_names = kind == VBL_PY_Z ? z_names : (channels == 1 ? y_names : NULL);
        l->pixels = px;
        l->store_half = kind != VBL_PY_Z && kind != VBL_PY_SAMPLES &&
                        (o->half_all || vbl_py_list_has(o->half_layers, kind == VBL_PY_BEAUTY ? "beauty" : name));
        kinds[count - 1] = kind;
        if (convert && channels >= 3 && kind != VBL_PY_Z && kind != VBL_PY_SAMPLES) {
            owned[count - 1] = vbl_py_convert_layer(px, n, channels, matrix, kind == VBL_PY_VARIANCE);
            if (!owned[count - 1]) r = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory converting colours", path);
            else l->pixels = owned[count - 1];
        }
    }
    if (!r && convert) { /* the layers still sum to the beauty exactly, in film order */
        const float* transport[VBL_PY_MAX_LAYERS];
        int transport_channels[VBL_PY_MAX_LAYERS], transport_count = 0, beauty = -1;
        for (int k = 0; k < count; ++k) {
            if (kinds[k] == VBL_PY_BEAUTY) beauty = k;
            if (kinds[k] == VBL_PY_TRANSPORT && layers[k].channel_count >= 3)
                transport[transport_count] = layers[k].pixels, transport_channels[transport_count++] = layers[k].channel_count;
        }
        if (beauty >= 0 && transport_count > 0 && owned[beauty])
            vbl_py_resum_beauty(owned[beauty], layers[beauty].channel_count, transport, transport_channels,
                                transport_count, n);
    }
    float chroma[8];
    int have_chroma = vbl_color_space_chromaticities(vbl_py_color_config(color), output, chroma) == VBL_SUCCESS;
    vbl_clear_error(); /* unknown primaries: no chromaticities attribute, as `vbl render` */
    vbl_exr_write_options wo = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    wo.attributes = m->attrs;
    wo.attribute_count = m->count;
    if (o->compression >= 0) wo.compression = (vbl_exr_compression)o->compression;
    wo.color_space = output;
    wo.chromaticities = have_chroma ? chroma : NULL;
    if (!r) r = vbl_exr_write(path, vbl_film_width(film), vbl_film_height(film), layers, count, &wo);
    for (int k = 0; k < count; ++k) free(owned[k]);
    vbl_py_color_release(own);
    free(m);
    return r;
}

/* `vbl render` outputs: the film's layers converted to the output colour space, the EXR with its
 * metadata (docs/readme/output.md, "Metadata"), and the PNG preview through OCIO. */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "exr_film.h"
#include "merge.h"
#include "render_cli.h"

#if defined(__has_include)
#if __has_include("vbl_exr.h")
#include "vbl_exr.h"
#define VBL_RENDER_HAVE_EXR 1
#endif
#if defined(VBL_CLI_HAVE_COLOR) && __has_include("vbl_color.h")
#include "vbl_color.h"
#define VBL_RENDER_HAVE_COLOR 1
#endif
#endif

#define VBL_RENDER_MAX_LAYERS 32

struct vbl_render_output {
    const vbl_render_args* args;
    char scene_hash[40];      /* "fnv1a64:<16 hex digits>" of the scene file's bytes */
    const char* scene_space;  /* the config's scene_linear colour space: the film's space */
    const char* output_space; /* the EXR's colour space */
    int convert;              /* output_space differs from scene_space */
    double m[9];              /* scene_space -> output_space, row-major, linear */
    float chroma[8];
    int have_chroma;
#ifdef VBL_RENDER_HAVE_COLOR
    vbl_color_config* config;
#endif
    char media[4096];         /* vbl:media: the scene's VDB paths (realpath), ';'-separated */
    float world_to_camera[16], world_to_ndc[16]; /* worldToCamera, worldToNDC (vbl_scene_camera_matrices) */
    int have_camera;
    /* --resume: the checkpoint merged into every file written */
    vbl_exr_image* base;
    int base_passes, base_first_pass;
    double base_seconds;
};

void vbl_render_output_set_scene(vbl_render_output* o, const vbl_scene* scene)
{
    double w2c[16], w2n[16];
    o->have_camera = vbl_scene_camera_matrices(scene, w2c, w2n) == VBL_SUCCESS;
    for (int e = 0; e < 16; ++e) {
        o->world_to_camera[e] = (float)w2c[e];
        o->world_to_ndc[e] = (float)w2n[e];
    }
    size_t used = 0;
    o->media[0] = 0;
    for (int i = 0; i < vbl_scene_medium_count(scene); ++i) {
        const char* path = vbl_scene_medium_path(scene, i);
        char* real = path ? realpath(path, NULL) : NULL;
        int n = snprintf(o->media + used, sizeof o->media - used, "%s%s", i ? ";" : "",
                         real ? real : (path ? path : ""));
        free(real);
        if (n < 0 || (size_t)n >= sizeof o->media - used) break;
        used += (size_t)n;
    }
}

void vbl_render_output_set_base(vbl_render_output* o, vbl_exr_image* base, int passes, int first_pass,
                                double seconds)
{
    if (base) vbl_exr_image_retain(base);
    if (o->base) vbl_exr_image_release(o->base);
    o->base = base;
    o->base_passes = base ? passes : 0;
    o->base_first_pass = first_pass;
    o->base_seconds = seconds;
}

/* ---- checks made before rendering -------------------------------------------------------- */

/* The directory of `path` must exist and be writable (outputs are renamed into it). */
static vbl_result vbl_render_check_dir(const char* path, const char* what)
{
    const char* slash = strrchr(path, '/');
    char dir[4096];
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == path) snprintf(dir, sizeof dir, "/");
    else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot write the %s: directory '%s' does not exist", path,
                                what, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot write the %s: directory '%s' is not writable (%s)",
                                path, what, dir, strerror(errno));
    if (slash && !slash[1])
        return vbl_report_error(VBL_ERROR_FILE_IO, "%s: the %s path names a directory", path, what);
    return VBL_SUCCESS;
}

/* The output format is given by the option, not guessed from the name: a path whose extension
 * names another format (out.png for -o) is refused, so no file holds bytes its name belies. */
static vbl_result vbl_render_check_extension(const char* path, const char* ext, const char* flag, const char* what)
{
    const char* slash = strrchr(path, '/');
    const char* base = slash ? slash + 1 : path;
    const char* dot = strrchr(base, '.');
    if (dot && !strcasecmp(dot, ext)) return VBL_SUCCESS;
    return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                            "%s: %s writes %s; name it *%s (%s)", path, flag, what, ext,
                            dot ? "its extension names another format" : "it has no extension");
}

/* FNV-1a 64 of the scene file's bytes (offset basis 0xcbf29ce484222325, prime 0x100000001b3). */
static vbl_result vbl_render_hash_scene(const char* path, char out[40])
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

/* 1 if `name` is a total layer (volume_indirect, surface_indirect). */
static int vbl_render_is_total(const char* p, size_t n)
{
    return (n == strlen(VBL_FILM_TOTAL_VOLUME_INDIRECT) && !strncmp(p, VBL_FILM_TOTAL_VOLUME_INDIRECT, n)) ||
           (n == strlen(VBL_FILM_TOTAL_SURFACE_INDIRECT) && !strncmp(p, VBL_FILM_TOTAL_SURFACE_INDIRECT, n));
}

/* Layer names accepted by --half-layers: beauty, the transport classes (vbl_transport_class_name),
 * the totals, variance. */
static int vbl_render_is_colour_layer(const char* p, size_t n)
{
    if ((n == 6 && !strncmp(p, "beauty", 6)) || (n == 8 && !strncmp(p, "variance", 8))) return 1;
    if (vbl_render_is_total(p, n)) return 1;
    if (n > 11 && !strncmp(p, "lightgroup_", 11)) return 1;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        const char* name = vbl_transport_class_name((vbl_transport_class)c);
        if (strlen(name) == n && !strncmp(p, name, n)) return 1;
    }
    return 0;
}

static int vbl_render_list_has(const char* list, const char* name)
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

static vbl_result vbl_render_check_half_layers(const char* list)
{
    for (const char* p = list; p && *p;) {
        size_t n = strcspn(p, ",");
        int known = vbl_render_is_colour_layer(p, n);
        if (!known)
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                    "--half-layers: '%.*s' is not a colour layer (beauty, background, volume_direct, "
                                    "volume_from_volume, ..., volume_indirect, surface_indirect, variance; Z and "
                                    "samples are always FLOAT)",
                                    (int)n, p);
        p += n;
        if (*p == ',') ++p;
    }
    return VBL_SUCCESS;
}

#ifdef VBL_RENDER_HAVE_COLOR
/* The scene_linear -> output matrix, read off the conversion of the unit vectors; the space must
 * be linear (a display-encoded space would break "layers sum to beauty"). */
static vbl_result vbl_render_output_matrix(vbl_render_output* o)
{
    for (int c = 0; c < 3; ++c) {
        float e[3] = {0.0f, 0.0f, 0.0f};
        e[c] = 1.0f;
        vbl_result r = vbl_color_convert_rgb(o->config, o->scene_space, o->output_space, e);
        if (r) return r;
        for (int k = 0; k < 3; ++k) o->m[3 * k + c] = e[k];
    }
    static const float probes[2][3] = {{0.02f, 0.5f, 3.0f}, {40.0f, 0.25f, 0.125f}};
    for (int p = 0; p < 2; ++p) {
        float v[3] = {probes[p][0], probes[p][1], probes[p][2]};
        vbl_result r = vbl_color_convert_rgb(o->config, o->scene_space, o->output_space, v);
        if (r) return r;
        for (int k = 0; k < 3; ++k) {
            double want = o->m[3 * k] * probes[p][0] + o->m[3 * k + 1] * probes[p][1] + o->m[3 * k + 2] * probes[p][2];
            if (!(fabs(want - v[k]) <= 1e-4 * (1.0 + fabs(want))))
                return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                        "--output-space '%s' is not a scene-linear colour space (the EXR holds "
                                        "linear radiance; use a display space only for --preview)",
                                        o->output_space);
        }
    }
    return VBL_SUCCESS;
}
#endif

#ifdef VBL_RENDER_HAVE_COLOR
/* vbl_scene_load_options.convert_color: a scene colour from the scene's "color_space" into the
 * config's scene_linear space (the film's space) through OCIO. Failures are VBL_ERROR_SCENE (the
 * loader prefixes the scene file, `color_space` and the field). */
static vbl_result vbl_render_convert_scene_color(void* user, const char* color_space, const char* field,
                                                 double rgb[3])
{
    (void)field;
    const vbl_render_output* o = user;
    const char* space = NULL;
    vbl_result r = vbl_color_resolve_space(o->config, color_space, &space);
    float v[3] = {(float)rgb[0], (float)rgb[1], (float)rgb[2]};
    if (!r) r = vbl_color_convert_rgb(o->config, space, o->scene_space, v);
    if (r) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        return vbl_report_error(VBL_ERROR_SCENE, "%s", msg);
    }
    for (int i = 0; i < 3; ++i) rgb[i] = v[i];
    return VBL_SUCCESS;
}
#endif

/* The scene's color_space must be known even when no colour needed converting. */
vbl_result vbl_render_output_check_scene(const vbl_render_output* o, const vbl_scene* scene)
{
#ifdef VBL_RENDER_HAVE_COLOR
    const char* space = vbl_scene_color_space(scene);
    const char* resolved = NULL;
    if (space && vbl_color_resolve_space(o->config, space, &resolved)) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        return vbl_report_error(VBL_ERROR_SCENE, "%s: color_space = \"%s\": %s", vbl_scene_path(scene), space, msg);
    }
#else
    (void)o;
    (void)scene;
#endif
    return VBL_SUCCESS;
}

void vbl_render_output_scene_load_options(vbl_render_output* o, vbl_scene_load_options* load)
{
#ifdef VBL_RENDER_HAVE_COLOR
    load->convert_color = vbl_render_convert_scene_color;
    load->convert_color_user = o;
#else
    (void)o;
    (void)load; /* no OCIO: a scene naming a color_space fails to load, saying why */
#endif
}

vbl_result vbl_render_output_create(const vbl_render_args* args, vbl_render_output** out)
{
    *out = NULL;
    vbl_render_output* o = calloc(1, sizeof *o);
    if (!o) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "vbl render: out of memory");
    o->args = args;
    vbl_result r = vbl_render_check_extension(args->output, ".exr", "-o", "an OpenEXR file");
    if (!r && args->preview) r = vbl_render_check_extension(args->preview, ".png", "--preview", "a PNG file");
    if (!r) r = vbl_render_check_dir(args->output, "output EXR");
    if (!r && args->preview) r = vbl_render_check_dir(args->preview, "preview PNG");
    if (!r) r = vbl_render_check_half_layers(args->half_layers);
    if (!r) r = vbl_render_hash_scene(args->scene_path, o->scene_hash);
#ifdef VBL_RENDER_HAVE_COLOR
    if (!r) r = vbl_color_config_open(args->config, &o->config);
    if (!r) r = vbl_color_resolve_space(o->config, "scene_linear", &o->scene_space);
    if (!r) {
        o->output_space = o->scene_space;
        if (args->output_space) r = vbl_color_resolve_space(o->config, args->output_space, &o->output_space);
        if (r) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
            r = vbl_report_error(r, "--output-space: %s", msg);
        }
    }
    if (!r && strcmp(o->output_space, o->scene_space)) {
        o->convert = 1;
        r = vbl_render_output_matrix(o);
    }
    if (!r) {
        o->have_chroma = vbl_color_space_chromaticities(o->config, o->output_space, o->chroma) == VBL_SUCCESS;
        vbl_clear_error(); /* unknown primaries: no chromaticities attribute (documented) */
    }
    if (!r && args->preview) { /* an unknown display/view fails now, not after the render */
        float probe[3] = {0.18f, 0.18f, 0.18f};
        r = vbl_color_display_view(o->config, o->output_space, args->display, args->view, (float)args->exposure,
                                   probe, 1, 3);
    }
#else
    if (!r && (args->output_space || args->config || args->preview || args->display || args->view))
        r = vbl_report_error(VBL_ERROR_UNSUPPORTED,
                             "this vbl was built without OpenColorIO: --output-space/--config/--preview unavailable");
#endif
    if (r) {
        vbl_render_output_destroy(o);
        return r;
    }
    *out = o;
    return VBL_SUCCESS;
}

void vbl_render_output_destroy(vbl_render_output* o)
{
    if (!o) return;
#ifdef VBL_RENDER_HAVE_COLOR
    vbl_color_config_release(o->config);
#endif
    if (o->base) vbl_exr_image_release(o->base);
    free(o);
}

/* ---- layers ------------------------------------------------------------------------------ */

typedef enum {
    VBL_KIND_BEAUTY,
    VBL_KIND_TRANSPORT,
    VBL_KIND_Z,
    VBL_KIND_SAMPLES,
    VBL_KIND_VARIANCE,
    VBL_KIND_TOTAL, /* volume_indirect, surface_indirect: sums of transport layers */
    VBL_KIND_GROUP  /* lightgroup_<name>: a light group's beauty (not re-summed) */
} vbl_layer_kind;

static vbl_layer_kind vbl_render_layer_kind(const char* name)
{
    if (!name[0]) return VBL_KIND_BEAUTY;
    if (vbl_render_is_total(name, strlen(name))) return VBL_KIND_TOTAL;
    if (!strncmp(name, "lightgroup_", 11)) return VBL_KIND_GROUP;
    if (!strcmp(name, "Z")) return VBL_KIND_Z;
    if (!strcmp(name, "samples")) return VBL_KIND_SAMPLES;
    if (!strcmp(name, "variance")) return VBL_KIND_VARIANCE;
    return VBL_KIND_TRANSPORT;
}

/* The film's layers as written: AOVs filtered, RGB converted to the output space. Converted
 * transport layers are re-summed (in film order, in float) into the beauty so that the layers
 * still add up to it exactly; variances transform with the element-wise squared matrix
 * (channels treated as uncorrelated). `owned` holds the buffers to free. */
typedef struct vbl_render_layers {
    const char* names[VBL_RENDER_MAX_LAYERS];
    const float* pixels[VBL_RENDER_MAX_LAYERS];
    int channels[VBL_RENDER_MAX_LAYERS];
    vbl_layer_kind kinds[VBL_RENDER_MAX_LAYERS];
    float* owned[VBL_RENDER_MAX_LAYERS];
    int count;
} vbl_render_layers;

static void vbl_render_layers_free(vbl_render_layers* L)
{
    for (int i = 0; i < L->count; ++i) free(L->owned[i]);
}

static vbl_result vbl_render_layers_make(const vbl_render_output* o, const vbl_film* film, vbl_render_layers* L)
{
    memset(L, 0, sizeof *L);
    const size_t n = (size_t)vbl_film_width(film) * (size_t)vbl_film_height(film);
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    int beauty = -1, transport_count = 0;
    for (int i = 0; i < vbl_film_layer_count(film) && L->count < VBL_RENDER_MAX_LAYERS; ++i) {
        const char* name = vbl_film_layer_name(film, i);
        vbl_layer_kind kind = vbl_render_layer_kind(name);
        if ((kind == VBL_KIND_Z && !o->args->aov_z) || (kind == VBL_KIND_SAMPLES && !o->args->aov_samples) ||
            (kind == VBL_KIND_VARIANCE && !o->args->aov_variance))
            continue;
        int channels = 0;
        const float* px = vbl_film_layer(film, name, &channels);
        if (!px) continue;
        int k = L->count++;
        L->names[k] = name;
        L->pixels[k] = px;
        L->channels[k] = channels;
        L->kinds[k] = kind;
        if (kind == VBL_KIND_BEAUTY) beauty = k;
        if (kind == VBL_KIND_TRANSPORT) ++transport_count;
        if (!o->convert || channels < 3 || kind == VBL_KIND_Z || kind == VBL_KIND_SAMPLES) continue;
        float* copy = malloc(sizeof(float) * n * (size_t)channels);
        if (!copy) {
            vbl_render_layers_free(L);
            return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "vbl render: out of memory converting colours");
        }
        memcpy(copy, px, sizeof(float) * n * (size_t)channels);
        double m[9];
        for (int e = 0; e < 9; ++e) m[e] = kind == VBL_KIND_VARIANCE ? o->m[e] * o->m[e] : o->m[e];
        for (size_t p = 0; p < n; ++p) {
            float* v = copy + p * (size_t)channels;
            double x = v[0], y = v[1], z = v[2];
            for (int r = 0; r < 3; ++r) v[r] = (float)(m[3 * r] * x + m[3 * r + 1] * y + m[3 * r + 2] * z);
        }
        L->owned[k] = copy;
        L->pixels[k] = copy;
    }
    if (o->convert && beauty >= 0 && transport_count > 0) {
        float* b = L->owned[beauty];
        for (size_t p = 0; p < n; ++p) {
            float sum[3] = {0.0f, 0.0f, 0.0f};
            for (int k = 0; k < L->count; ++k)
                if (L->kinds[k] == VBL_KIND_TRANSPORT &&
                    !(stats.transparent && !strcmp(L->names[k], vbl_transport_class_name(VBL_CLASS_BACKGROUND))))
                    for (int c = 0; c < 3; ++c) sum[c] += L->pixels[k][p * (size_t)L->channels[k] + (size_t)c];
            for (int c = 0; c < 3; ++c) b[p * (size_t)L->channels[beauty] + (size_t)c] = sum[c];
        }
    }
    /* the totals, re-summed from the converted classes (class order, float) as the film sums them */
    for (int t = 0; o->convert && t < L->count; ++t) {
        if (L->kinds[t] != VBL_KIND_TOTAL || !L->owned[t]) continue;
        const int volume = !strcmp(L->names[t], VBL_FILM_TOTAL_VOLUME_INDIRECT);
        static const char* const volume_members[2] = {"volume_from_surface", "volume_from_volume"};
        static const char* const surface_members[2] = {"surface_from_surface", "surface_from_volume"};
        const char* const* members = volume ? volume_members : surface_members;
        const float* src[2] = {NULL, NULL};
        for (int k = 0; k < L->count; ++k)
            for (int m = 0; m < 2; ++m)
                if (L->kinds[k] == VBL_KIND_TRANSPORT && !strcmp(L->names[k], members[m])) src[m] = L->pixels[k];
        for (size_t v = 0; v < 3 * n; ++v) {
            float sum = 0.0f;
            for (int m = 0; m < 2; ++m)
                if (src[m]) sum += src[m][v];
            L->owned[t][v] = sum;
        }
    }
    return VBL_SUCCESS;
}

/* ---- EXR --------------------------------------------------------------------------------- */

static int vbl_render_store_half(const vbl_render_args* a, const char* name, vbl_layer_kind kind)
{
    if (kind == VBL_KIND_Z || kind == VBL_KIND_SAMPLES) return 0;
    return a->half_all || vbl_render_list_has(a->half_layers, kind == VBL_KIND_BEAUTY ? "beauty" : name);
}

/* The EXR channel name of channel c of layer k ("R", "A", "Z", "samples.Y", "emission.G"). */
static void vbl_render_channel_name(const vbl_render_layers* L, int k, int c, char* out, size_t size)
{
    static const char* const rgba[4] = {"R", "G", "B", "A"};
    if (L->kinds[k] == VBL_KIND_Z) snprintf(out, size, "Z");
    else if (L->kinds[k] == VBL_KIND_BEAUTY) snprintf(out, size, "%s", rgba[c]);
    else snprintf(out, size, "%s.%s", L->names[k], L->channels[k] == 1 ? "Y" : rgba[c]);
}

/* --resume: L becomes the library's merge (vbl_film_merge) of the checkpoint (o->base, its
 * o->base_passes passes) and this film (film_passes passes), layer by layer as written. */
static vbl_result vbl_render_layers_merge_base(const vbl_render_output* o, vbl_render_layers* L, int width,
                                               int height, int film_passes)
{
    const size_t n = (size_t)width * (size_t)height;
    vbl_film* whole = NULL; /* every channel of the checkpoint */
    vbl_result r = vbl_cli_film_from_exr(o->base, o->args->output, o->base_passes, &whole);
    if (r) return r;
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(whole, &stats);
    stats.first_pass = o->base_first_pass;
    vbl_film *base = NULL, *part = NULL, *merged = NULL;
    r = vbl_film_create(width, height, &stats, &base);
    stats.passes = film_passes;
    stats.first_pass = o->base_first_pass + o->base_passes;
    if (!r) r = vbl_film_create(width, height, &stats, &part);
    float* buffer = malloc(sizeof(float) * 4 * (n ? n : 1));
    float* plane = malloc(sizeof(float) * (n ? n : 1));
    if (!r && (!buffer || !plane)) r = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "vbl render: out of memory merging the checkpoint");
    for (int k = 0; !r && k < L->count; ++k) {
        char full[4][256];
        const char* names[4];
        for (int c = 0; c < L->channels[k]; ++c) {
            vbl_render_channel_name(L, k, c, full[c], sizeof full[c]);
            const char* dot = strrchr(full[c], '.');
            names[c] = dot ? dot + 1 : full[c];
            if (!vbl_cli_film_channel(whole, full[c], plane, n)) {
                r = vbl_report_error(VBL_ERROR_SCENE,
                                     "%s: the checkpoint has no channel '%s' (resume with the same --aov flags)",
                                     o->args->output, full[c]);
                break;
            }
            for (size_t i = 0; i < n; ++i) buffer[(size_t)L->channels[k] * i + (size_t)c] = plane[i];
        }
        if (!r) r = vbl_film_add_layer(base, L->names[k], L->channels[k], names, buffer);
        if (!r) r = vbl_film_add_layer(part, L->names[k], L->channels[k], names, L->pixels[k]);
    }
    const vbl_film* films[2] = {base, part};
    if (!r) r = vbl_film_merge(films, 2, &merged);
    for (int k = 0; !r && k < L->count; ++k) {
        size_t values = n * (size_t)L->channels[k];
        float* copy = malloc(sizeof(float) * (values ? values : 1));
        if (!copy) {
            r = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "vbl render: out of memory merging the checkpoint");
            break;
        }
        memcpy(copy, vbl_film_layer(merged, L->names[k], NULL), sizeof(float) * values);
        free(L->owned[k]);
        L->owned[k] = copy;
        L->pixels[k] = copy;
    }
    free(buffer);
    free(plane);
    vbl_film_release(merged);
    vbl_film_release(part);
    vbl_film_release(base);
    vbl_film_release(whole);
    return r;
}

#define VBL_RENDER_MAX_ATTRS 32

/* The EXR header attributes (docs/readme/output.md, "Metadata"; docs/readme/pipeline.md). */
typedef struct vbl_render_meta {
    char software[64], seed[32], options_hash[40], pass_range[64];
    vbl_exr_attribute attrs[VBL_RENDER_MAX_ATTRS];
    int count;
} vbl_render_meta;

static void vbl_render_meta_add(vbl_render_meta* m, const char* name, const char* value, vbl_exr_attribute_type type,
                                int int_value, double double_value)
{
    if (m->count >= VBL_RENDER_MAX_ATTRS) return;
    vbl_exr_attribute* a = &m->attrs[m->count++];
    a->name = name;
    a->value = value;
    a->type = type;
    a->int_value = int_value;
    a->double_value = double_value;
}

/* `stats`: the film's (or, before rendering, the options'); passes = every pass in the file,
 * first_pass = the absolute index of its first pass. */
static void vbl_render_meta_make(const vbl_render_output* o, const vbl_film_stats* stats,
                                 const vbl_render_options* options, int passes, int first_pass, int passes_requested,
                                 const char* status, double wall_seconds, vbl_render_meta* m)
{
    const vbl_exr_attribute_type S = VBL_EXR_ATTRIBUTE_STRING, I = VBL_EXR_ATTRIBUTE_INT, D = VBL_EXR_ATTRIBUTE_DOUBLE;
    const vbl_render_args* a = o->args;
    memset(m, 0, sizeof *m);
    snprintf(m->software, sizeof m->software, "vbl %s", vbl_version_string());
    snprintf(m->seed, sizeof m->seed, "%llu", (unsigned long long)stats->seed);
    vbl_render_options_hash(options, m->options_hash, sizeof m->options_hash);
    vbl_render_meta_add(m, "software", m->software, S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:version", vbl_version_string(), S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:scene", a->scene_path, S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:scene_hash", o->scene_hash, S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:media", o->media, S, 0, 0.0);
    if (a->has_frame) vbl_render_meta_add(m, "vbl:frame", NULL, I, a->frame, 0.0);
    vbl_render_meta_add(m, "vbl:method", vbl_render_method_name(stats->method), S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:preset", a->preset ? a->preset : "none", S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:status", status, S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:passes", NULL, I, passes, 0.0);
    vbl_render_meta_add(m, "vbl:passes_requested", NULL, I, passes_requested, 0.0);
    vbl_render_meta_add(m, "vbl:first_pass", NULL, I, first_pass, 0.0);
    if (a->pass_first >= 0) {
        snprintf(m->pass_range, sizeof m->pass_range, "%ld-%ld", a->pass_first, a->pass_last);
        vbl_render_meta_add(m, "vbl:pass_range", m->pass_range, S, 0, 0.0);
    }
    vbl_render_meta_add(m, "vbl:spp", NULL, I, stats->spp, 0.0);
    vbl_render_meta_add(m, "vbl:light_paths", NULL, I, stats->light_paths, 0.0);
    vbl_render_meta_add(m, "vbl:seed", m->seed, S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:options_hash", m->options_hash, S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:threads", NULL, I, stats->threads, 0.0);
    vbl_render_meta_add(m, "vbl:max_bounces", NULL, I, options->max_bounces, 0.0);
    vbl_render_meta_add(m, "vbl:transmittance", vbl_transmittance_estimator_name(options->transmittance), S, 0, 0.0);
    vbl_render_meta_add(m, "vbl:render_seconds", NULL, D, 0, wall_seconds);
    vbl_render_meta_add(m, "vbl:alpha",
                        options->transparent
                            ? "premultiplied; A = 1 - transmittance along the camera ray; the beauty leaves out the "
                              "background layer (transparent)"
                            : "premultiplied; A = 1 - transmittance along the camera ray (1 where a background layer "
                              "is rendered: it is in the beauty)",
                        S, 0, 0.0);
    if (options->transparent) vbl_render_meta_add(m, "vbl:transparent", NULL, I, 1, 0.0);
    if (o->have_camera) {
        vbl_render_meta_add(m, "worldToCamera", NULL, VBL_EXR_ATTRIBUTE_M44F, 0, 0.0);
        m->attrs[m->count - 1].m44 = o->world_to_camera;
        vbl_render_meta_add(m, "worldToNDC", NULL, VBL_EXR_ATTRIBUTE_M44F, 0, 0.0);
        m->attrs[m->count - 1].m44 = o->world_to_ndc;
    }
    vbl_render_meta_add(m, "vbl:scene_color_space", o->scene_space ? o->scene_space : "scene_linear", S, 0, 0.0);
    /* written by the EXR writer from write options; listed here for the identity checks */
    if (o->output_space) vbl_render_meta_add(m, "oiio:ColorSpace", o->output_space, S, 0, 0.0);
}

vbl_result vbl_render_output_check_resume(vbl_render_output* o, const vbl_scene* scene,
                                          const vbl_render_options* options, const vbl_exr_image* image)
{
    const char* path = o->args->output;
    const char* status = vbl_exr_image_attribute(image, "vbl:status", NULL);
    const char* passes_text = vbl_exr_image_attribute(image, "vbl:passes", NULL);
    const char* first_text = vbl_exr_image_attribute(image, "vbl:first_pass", NULL);
    if (!status || !passes_text || !first_text)
        return vbl_report_error(VBL_ERROR_SCENE,
                                "%s: cannot resume: not a vbl render checkpoint (no vbl:status / vbl:passes / "
                                "vbl:first_pass); move it away or drop --resume",
                                path);
    if (strcmp(status, "checkpoint") && strcmp(status, "interrupted") && strcmp(status, "time_limit") &&
        strcmp(status, "complete"))
        return vbl_report_error(VBL_ERROR_SCENE, "%s: cannot resume: vbl:status = \"%s\"", path, status);
    if (atoi(passes_text) < 1)
        return vbl_report_error(VBL_ERROR_SCENE, "%s: cannot resume: vbl:passes = %s", path, passes_text);
    if (atoi(first_text) != options->first_pass)
        return vbl_report_error(VBL_ERROR_SCENE,
                                "%s: cannot resume: vbl:first_pass = %s but this render starts at pass %d", path,
                                first_text, options->first_pass);
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.method = options->method;
    stats.spp = options->spp;
    stats.light_paths = vbl_render_options_light_paths(options);
    stats.seed = options->seed;
    vbl_render_meta m;
    vbl_render_meta_make(o, &stats, options, 0, options->first_pass, 0, "checkpoint", 0.0, &m);
    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    vbl_merge_identity want, have;
    vbl_merge_identity_from_attributes(m.attrs, m.count, w, h, &want);
    vbl_merge_identity_from_image(image, &have);
    char msg[4096];
    if (vbl_merge_identity_compare(&want, "this render", &have, path, msg, sizeof msg))
        return vbl_report_error(VBL_ERROR_SCENE, "cannot resume: %s", msg);
    static const char* const aov_channels[3] = {"samples.Y", "variance.R", "Z"};
    int wanted[3] = {o->args->aov_samples, o->args->aov_variance,
                     o->args->aov_z && vbl_scene_medium_count(scene) > 0};
    for (int i = 0; i < 3; ++i)
        if ((vbl_exr_image_find_channel(image, aov_channels[i]) >= 0) != wanted[i])
            return vbl_report_error(VBL_ERROR_SCENE,
                                    "cannot resume: %s %s channel %s but this render %s it (use the same --aov)", path,
                                    wanted[i] ? "lacks" : "has", aov_channels[i], wanted[i] ? "writes" : "does not write");
    return VBL_SUCCESS;
}

vbl_result vbl_render_output_write_exr(vbl_render_output* o, const vbl_film* film, const vbl_render_options* options,
                                       int passes_requested, const char* status, double wall_seconds)
{
    vbl_render_layers L;
    vbl_result r = vbl_render_layers_make(o, film, &L);
    if (r) return r;
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    int passes = stats.passes, first_pass = stats.first_pass;
    if (o->base) {
        r = vbl_render_layers_merge_base(o, &L, vbl_film_width(film), vbl_film_height(film), stats.passes);
        if (r) {
            vbl_render_layers_free(&L);
            return r;
        }
        passes += o->base_passes;
        first_pass = o->base_first_pass;
        wall_seconds += o->base_seconds;
    }
    static const char* const z_names[1] = {"Z"};
    static const char* const y_names[1] = {"Y"};
    vbl_exr_layer layers[VBL_RENDER_MAX_LAYERS];
    for (int i = 0; i < L.count; ++i) {
        vbl_exr_layer* l = &layers[i];
        memset(l, 0, sizeof *l);
        l->name = L.kinds[i] == VBL_KIND_Z ? "" : L.names[i];
        l->channel_count = L.channels[i];
        l->channel_names = L.kinds[i] == VBL_KIND_Z ? z_names : (L.channels[i] == 1 ? y_names : NULL);
        l->pixels = L.pixels[i];
        l->store_half = vbl_render_store_half(o->args, L.names[i], L.kinds[i]);
    }
    vbl_render_meta m;
    vbl_render_meta_make(o, &stats, options, passes, first_pass, passes_requested, status, wall_seconds, &m);
    if (o->output_space) --m.count; /* oiio:ColorSpace: written by the EXR writer (wo.color_space) */
    vbl_exr_write_options wo = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    wo.attributes = m.attrs;
    wo.attribute_count = m.count;
    if (o->args->compression >= 0) wo.compression = (vbl_exr_compression)o->args->compression;
    wo.tiled = o->args->tiled;
    wo.tile_size = o->args->tile_size;
    wo.color_space = o->output_space;
    wo.chromaticities = o->have_chroma ? o->chroma : NULL;
    r = vbl_exr_write(o->args->output, vbl_film_width(film), vbl_film_height(film), layers, L.count, &wo);
    vbl_render_layers_free(&L);
    return r;
}

/* ---- preview ----------------------------------------------------------------------------- */

vbl_result vbl_render_output_write_preview(vbl_render_output* o, const vbl_film* film)
{
    if (!o->args->preview) return VBL_SUCCESS;
#ifndef VBL_RENDER_HAVE_COLOR
    (void)film;
    return vbl_report_error(VBL_ERROR_UNSUPPORTED, "this vbl was built without OpenColorIO: no --preview");
#else
    vbl_render_layers L;
    vbl_result r = vbl_render_layers_make(o, film, &L);
    if (r) return r;
    int beauty = -1;
    for (int i = 0; i < L.count; ++i)
        if (L.kinds[i] == VBL_KIND_BEAUTY) beauty = i;
    if (beauty < 0) r = vbl_report_error(VBL_ERROR_INTERNAL, "vbl render: the film has no beauty layer");
    if (!r) {
        vbl_preview_options po = VBL_PREVIEW_OPTIONS_DEFAULT;
        po.config = o->config;
        po.input_space = o->output_space;
        po.display = o->args->display;
        po.view = o->args->view;
        po.exposure = (float)o->args->exposure;
        r = vbl_preview_write_png(o->args->preview, L.pixels[beauty], vbl_film_width(film), vbl_film_height(film),
                                  L.channels[beauty], &po);
    }
    vbl_render_layers_free(&L);
    return r;
#endif
}

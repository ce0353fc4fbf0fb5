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

#include "vbl_render_exr.h"

#if defined(VBL_CLI_HAVE_COLOR) && defined(VBL_RENDER_EXR_HAVE_COLOR)
#define VBL_RENDER_HAVE_COLOR 1
#endif

struct vbl_render_output {
    const vbl_render_args* args;
    /* what the EXR holds besides the film (plugins/render_exr): scene hash and media, camera
     * matrices, frame, preset, pass range, AOVs, HALF layers, compression, colour spaces */
    vbl_render_exr_settings exr;
    const char* scene_space;  /* the config's scene_linear colour space: the film's space */
    const char* output_space; /* the EXR's colour space */
#ifdef VBL_RENDER_HAVE_COLOR
    vbl_color_config* config;
    vbl_color_scene_target color_target; /* {config, scene_space}: the scene loader's colour hook */
#endif
    /* --resume: the checkpoint merged into every file written */
    vbl_exr_image* base;
    int base_passes, base_first_pass;
    double base_seconds;
};

void vbl_render_output_set_scene(vbl_render_output* o, const vbl_scene* scene)
{
    vbl_render_exr_set_scene(&o->exr, scene);
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


/* The scene's color_space must be known even when no colour needed converting. */
vbl_result vbl_render_output_check_scene(const vbl_render_output* o, const vbl_scene* scene)
{
#ifdef VBL_RENDER_HAVE_COLOR
    vbl_result r = vbl_color_check_scene_space(o->config, vbl_scene_path(scene), vbl_scene_color_space(scene));
    if (r) return r;
#else
    (void)o;
    (void)scene;
#endif
    return VBL_SUCCESS;
}

void vbl_render_output_scene_load_options(vbl_render_output* o, vbl_scene_load_options* load)
{
#ifdef VBL_RENDER_HAVE_COLOR
    load->convert_color = vbl_color_convert_scene_color;
    load->convert_color_user = &o->color_target;
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
    if (!r && vbl_render_exr_check_half_layers(args->half_layers)) {
        char msg[2048];
        snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
        r = vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "--half-layers: %s", msg);
    }
    vbl_render_exr_settings* x = &o->exr;
    vbl_render_exr_settings_init(x);
    x->scene_label = args->scene_path;
    x->has_frame = args->has_frame;
    x->frame = args->frame;
    x->preset = args->preset;
    x->pass_first = args->pass_first;
    x->pass_last = args->pass_last;
    x->aov_z = args->aov_z;
    x->aov_samples = args->aov_samples;
    x->aov_variance = args->aov_variance;
    x->half_all = args->half_all;
    x->half_layers = args->half_layers;
    x->compression = args->compression;
    x->tiled = args->tiled;
    x->tile_size = args->tile_size;
    if (!r) r = vbl_render_exr_hash_file(x, args->scene_path);
#ifdef VBL_RENDER_HAVE_COLOR
    if (!r) r = vbl_color_config_open(args->config, &o->config);
    if (!r) r = vbl_color_resolve_space(o->config, "scene_linear", &o->scene_space);
    o->color_target = (vbl_color_scene_target){o->config, o->scene_space};
    if (!r) {
        o->output_space = o->scene_space;
        if (args->output_space) r = vbl_color_resolve_space(o->config, args->output_space, &o->output_space);
        if (r) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
            r = vbl_report_error(r, "--output-space: %s", msg);
        }
    }
    if (!r) {
        r = vbl_render_exr_set_color(x, o->config, o->scene_space, o->output_space);
        if (r) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
            r = vbl_report_error(r, "--output-space: %s", msg);
        }
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

/* ---- EXR --------------------------------------------------------------------------------- */

/* --resume: L becomes the library's merge (vbl_film_merge) of the checkpoint (o->base, its
 * o->base_passes passes) and this film (film_passes passes), layer by layer as written. */
static vbl_result vbl_render_layers_merge_base(const vbl_render_output* o, vbl_render_exr_layers* L, int width,
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
            vbl_render_exr_channel_name(L, k, c, full[c], sizeof full[c]);
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
    stats.light_paths = vbl_render_light_paths(scene, options);
    stats.seed = options->seed;
    vbl_render_exr_meta m;
    vbl_render_exr_meta_make(&o->exr, &stats, options, 0, options->first_pass, 0, "checkpoint", 0.0, &m);
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
    vbl_render_exr_layers L;
    vbl_result r = vbl_render_exr_layers_make(&o->exr, film, &L);
    if (r) return r;
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    int passes = stats.passes, first_pass = stats.first_pass;
    if (o->base) {
        r = vbl_render_layers_merge_base(o, &L, vbl_film_width(film), vbl_film_height(film), stats.passes);
        if (r) {
            vbl_render_exr_layers_free(&L);
            return r;
        }
        passes += o->base_passes;
        first_pass = o->base_first_pass;
        wall_seconds += o->base_seconds;
    }
    vbl_render_exr_meta m;
    vbl_render_exr_meta_make(&o->exr, &stats, options, passes, first_pass, passes_requested, status, wall_seconds, &m);
    r = vbl_render_exr_write_layers(o->args->output, vbl_film_width(film), vbl_film_height(film), &o->exr, &L, &m);
    vbl_render_exr_layers_free(&L);
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
    vbl_render_exr_layers L;
    vbl_result r = vbl_render_exr_layers_make(&o->exr, film, &L);
    if (r) return r;
    int beauty = -1;
    for (int i = 0; i < L.count; ++i)
        if (L.kinds[i] == VBL_RENDER_EXR_BEAUTY) beauty = i;
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
    vbl_render_exr_layers_free(&L);
    return r;
#endif
}

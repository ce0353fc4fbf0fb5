/* `vbl render SCENE.json -o OUT.exr [options]`: renders a scene file to a multi-layer EXR
 * (beauty + one layer per transport class + AOVs), optionally with an 8-bit sRGB PNG preview.
 * Flags override the scene's `render` block. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <png.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

#if defined(__has_include)
#if __has_include("vbl_exr.h")
#include "vbl_exr.h"
#define VBL_CLI_HAVE_EXR 1
#endif
#endif

#define VBL_CLI_MAX_VDB 8

static volatile sig_atomic_t vbl_render_interrupted = 0;

static void vbl_render_on_signal(int sig)
{
    (void)sig;
    vbl_render_interrupted = 1;
}

static void vbl_render_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl render SCENE.json -o OUT.exr [options]\n\n"
            "Renders a scene file (docs: README 'Rendering') to a multi-layer OpenEXR: beauty (R,G,B,A),\n"
            "emission, volume_direct, volume_from_volume, Z, samples, variance. Options override the\n"
            "scene's \"render\" block.\n\n"
            "  -o, --output OUT.exr     output EXR (written to a temporary name, then renamed)\n"
            "  --method pt|vpl|vrl      rendering method\n"
            "  --passes N               progressive passes (N >= 1)\n"
            "  --spp N                  camera samples per pixel per pass (N >= 1)\n"
            "  --light-paths N          light paths per pass (vpl, vrl)\n"
            "  --seed S                 random seed (integer >= 0)\n"
            "  --time-limit SEC         stop after the pass that exceeds SEC seconds (0: none)\n"
            "  --max-bounces N          scattering events per path (-1: unlimited)\n"
            "  --transmittance NAME     delta|ratio|residual|march|cached-delta|cached-ratio\n"
            "  --threads N              worker threads (0: all cores)\n"
            "  --vdb PATH               replace media[i].vdb (i-th use -> media[i]); for sample scenes\n"
            "  --preview OUT.png        also write an 8-bit sRGB preview of the beauty\n"
            "  --half                   store the EXR layers as HALF (default FLOAT: layers sum to beauty)\n"
            "  -q, --quiet              no per-pass progress on stderr\n"
            "  -h, --help               this text\n\n"
            "Exit codes: 0 ok, 1 render failed, 2 bad command line, 3 bad scene/VDB, 4 cannot write,\n"
            "5 interrupted (the passes done so far are still written).\n");
}

static int vbl_parse_long(const char* text, long min, long max, long* out)
{
    char* end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || !end || *end || end == text || v < min || v > max) return 0;
    *out = v;
    return 1;
}

static int vbl_parse_double(const char* text, double* out)
{
    char* end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || !end || *end || end == text || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

typedef struct vbl_render_cli {
    int quiet;
} vbl_render_cli;

static int vbl_render_progress_cb(const vbl_render_progress* p, void* user)
{
    const vbl_render_cli* cli = user;
    if (!cli->quiet)
        fprintf(stderr, "vbl render: pass %d/%d  %.2f s (total %.2f s, %llu spp)\n", p->pass, p->passes,
                p->pass_seconds, p->elapsed_seconds, (unsigned long long)p->samples_per_pixel);
    return vbl_render_interrupted ? 1 : 0;
}

static float vbl_srgb_encode(float linear)
{
    if (!(linear > 0.0f)) return 0.0f;
    if (linear >= 1.0f) return 1.0f;
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
}

/* 8-bit sRGB PNG of the beauty (clamped to [0, 1]), written to a temporary name and renamed. */
static int vbl_write_preview(const char* path, const vbl_film* film)
{
    int channels = 0;
    const float* beauty = vbl_film_layer(film, "", &channels);
    int w = vbl_film_width(film), h = vbl_film_height(film);
    if (!beauty || channels < 3) return 0;
    size_t len = strlen(path);
    char* tmp = malloc(len + 16);
    unsigned char* row = malloc((size_t)w * 3);
    if (!tmp || !row) {
        free(tmp);
        free(row);
        return 0;
    }
    snprintf(tmp, len + 16, "%s.tmp%ld", path, (long)getpid());
    FILE* f = fopen(tmp, "wb");
    int ok = f != NULL;
    png_structp png = ok ? png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL) : NULL;
    png_infop info = png ? png_create_info_struct(png) : NULL;
    ok = ok && png && info;
    if (ok && setjmp(png_jmpbuf(png))) ok = 0;
    else if (ok) {
        png_init_io(png, f);
        png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
        png_write_info(png, info);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    row[3 * x + c] =
                        (unsigned char)lrintf(255.0f * vbl_srgb_encode(beauty[((size_t)y * w + x) * channels + c]));
            png_write_row(png, row);
        }
        png_write_end(png, NULL);
    }
    if (png) png_destroy_write_struct(&png, info ? &info : NULL);
    if (f && fclose(f) != 0) ok = 0;
    if (ok && rename(tmp, path) != 0) ok = 0;
    if (!ok) remove(tmp);
    free(tmp);
    free(row);
    return ok;
}

#ifdef VBL_CLI_HAVE_EXR
static vbl_result vbl_write_exr(const char* path, const vbl_film* film, const char* scene_path,
                                const vbl_render_options* options, int store_half)
{
    vbl_exr_layer layers[16];
    int count = 0;
    for (int i = 0; i < vbl_film_layer_count(film) && count < 16; ++i) {
        const char* name = vbl_film_layer_name(film, i);
        int channels = 0;
        const float* pixels = vbl_film_layer(film, name, &channels);
        vbl_exr_layer* l = &layers[count++];
        memset(l, 0, sizeof *l);
        /* depth is the standard unprefixed "Z" channel */
        static const char* const z_names[1] = {"Z"};
        static const char* const y_names[1] = {"Y"};
        l->name = strcmp(name, "Z") ? name : "";
        l->channel_count = channels;
        l->channel_names = !strcmp(name, "Z") ? z_names : (channels == 1 ? y_names : NULL);
        l->pixels = pixels;
        l->store_half = store_half && strcmp(name, "Z") && strcmp(name, "samples");
    }
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    char version[64], passes[32], spp[32], light_paths[32], seed[32], seconds[32], threads[32], bounces[32];
    snprintf(version, sizeof version, "vbl %s", vbl_version_string());
    snprintf(passes, sizeof passes, "%d", stats.passes);
    snprintf(spp, sizeof spp, "%d", stats.spp);
    snprintf(light_paths, sizeof light_paths, "%d", stats.light_paths);
    snprintf(seed, sizeof seed, "%llu", (unsigned long long)stats.seed);
    snprintf(seconds, sizeof seconds, "%.3f", stats.render_seconds);
    snprintf(threads, sizeof threads, "%d", stats.threads);
    snprintf(bounces, sizeof bounces, "%d", options->max_bounces);
    vbl_exr_attribute attrs[] = {
        {"software", version, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:version", vbl_version_string(), VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:scene", scene_path, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:method", vbl_render_method_name(stats.method), VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:passes", passes, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:spp", spp, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:light_paths", light_paths, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:seed", seed, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:render_seconds", seconds, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:threads", threads, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:max_bounces", bounces, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0},
        {"vbl:transmittance", vbl_transmittance_estimator_name(options->transmittance), VBL_EXR_ATTRIBUTE_STRING, 0,
         0.0},
    };
    vbl_exr_write_options wo = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    wo.attributes = attrs;
    wo.attribute_count = (int)(sizeof attrs / sizeof attrs[0]);
    return vbl_exr_write(path, vbl_film_width(film), vbl_film_height(film), layers, count, &wo);
}
#endif

int vbl_cmd_render(int argc, char** argv)
{
    const char* scene_path = NULL;
    const char* output = NULL;
    const char* preview = NULL;
    const char* method = NULL;
    const char* transmittance = NULL;
    const char* vdb[VBL_CLI_MAX_VDB] = {NULL};
    int vdb_count = 0, store_half = 0;
    long passes = -1, spp = -1, light_paths = -1, threads = 0, max_bounces = LONG_MIN, seed = -1;
    double time_limit = -1.0;
    vbl_render_cli cli = {0};

    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = 1, ok = 1;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            vbl_render_usage(stdout);
            return VBL_EXIT_OK;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            cli.quiet = 1;
            takes = 0;
        } else if (!strcmp(a, "--half")) {
            store_half = 1;
            takes = 0;
        } else if (a[0] != '-' || !a[1]) {
            if (scene_path) {
                fprintf(stderr, "vbl render: more than one scene file ('%s', '%s')\n", scene_path, a);
                return VBL_EXIT_USAGE;
            }
            scene_path = a;
            takes = 0;
        } else if (!v) {
            fprintf(stderr, "vbl render: %s needs a value (see 'vbl render --help')\n", a);
            return VBL_EXIT_USAGE;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) output = v;
        else if (!strcmp(a, "--preview")) preview = v;
        else if (!strcmp(a, "--method")) method = v;
        else if (!strcmp(a, "--transmittance")) transmittance = v;
        else if (!strcmp(a, "--passes")) ok = vbl_parse_long(v, 1, INT_MAX, &passes);
        else if (!strcmp(a, "--spp")) ok = vbl_parse_long(v, 1, INT_MAX, &spp);
        else if (!strcmp(a, "--light-paths")) ok = vbl_parse_long(v, 0, INT_MAX, &light_paths);
        else if (!strcmp(a, "--seed")) ok = vbl_parse_long(v, 0, LONG_MAX, &seed);
        else if (!strcmp(a, "--threads")) ok = vbl_parse_long(v, 0, 4096, &threads);
        else if (!strcmp(a, "--max-bounces")) ok = vbl_parse_long(v, -1, INT_MAX, &max_bounces);
        else if (!strcmp(a, "--time-limit")) ok = vbl_parse_double(v, &time_limit) && time_limit >= 0.0;
        else if (!strcmp(a, "--vdb")) {
            if (vdb_count >= VBL_CLI_MAX_VDB) {
                fprintf(stderr, "vbl render: at most %d --vdb overrides\n", VBL_CLI_MAX_VDB);
                return VBL_EXIT_USAGE;
            }
            vdb[vdb_count++] = v;
        } else {
            fprintf(stderr, "vbl render: unknown option '%s' (see 'vbl render --help')\n", a);
            return VBL_EXIT_USAGE;
        }
        if (!ok) {
            fprintf(stderr, "vbl render: invalid value '%s' for %s\n", v, a);
            return VBL_EXIT_USAGE;
        }
        i += takes;
    }
    if (!scene_path || !output) {
        vbl_render_usage(stderr);
        return VBL_EXIT_USAGE;
    }
#ifndef VBL_CLI_HAVE_EXR
    fprintf(stderr, "vbl render: this build has no EXR writer\n");
    return VBL_EXIT_FAILURE;
#else
    vbl_render_options options = VBL_RENDER_OPTIONS_DEFAULT;
    if (method && vbl_render_method_parse(method, &options.method)) {
        fprintf(stderr, "vbl render: --method '%s' is not one of pt, vpl, vrl\n", method);
        return VBL_EXIT_USAGE;
    }
    vbl_transmittance_estimator estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    if (transmittance && vbl_transmittance_estimator_parse(transmittance, &estimator)) {
        fprintf(stderr, "vbl render: --transmittance '%s' is not a transmittance estimator\n", transmittance);
        return VBL_EXIT_USAGE;
    }

    vbl_scene_load_options load = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    load.vdb_overrides = vdb;
    load.vdb_override_count = vdb_count;
    vbl_scene* scene = NULL;
    vbl_result r = vbl_scene_load_ex(scene_path, &load, &scene);
    if (r) return vbl_cli_fail(r);

    vbl_render_method chosen = options.method;
    vbl_scene_render_options(scene, &options);
    if (method) options.method = chosen;
    if (transmittance) options.transmittance = estimator;
    if (passes > 0) options.passes = (int)passes;
    if (spp > 0) options.spp = (int)spp;
    if (light_paths >= 0) options.light_paths = (int)light_paths;
    if (seed >= 0) options.seed = (uint64_t)seed;
    if (time_limit >= 0.0) options.time_limit = time_limit;
    if (max_bounces != LONG_MIN) options.max_bounces = (int)max_bounces;
    options.threads = (int)threads;
    options.callback = vbl_render_progress_cb;
    options.callback_user_data = &cli;

    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    if (!cli.quiet)
        fprintf(stderr, "vbl render: %s %dx%d, method %s, %d passes x %d spp, seed %llu\n", scene_path, w, h,
                vbl_render_method_name(options.method), options.passes, options.spp,
                (unsigned long long)options.seed);

    struct sigaction sa, old_int, old_term;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = vbl_render_on_signal;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    vbl_film* film = NULL;
    r = vbl_render(scene, &options, &film);
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    int exit_code = VBL_EXIT_OK;
    if (r && !(r == VBL_ERROR_INTERRUPTED && film)) {
        exit_code = vbl_cli_fail(r);
        vbl_scene_release(scene);
        return exit_code;
    }
    if (r == VBL_ERROR_INTERRUPTED) {
        fprintf(stderr, "vbl render: interrupted; writing the passes done so far\n");
        exit_code = VBL_EXIT_INTERRUPTED;
    }
    vbl_result wr = vbl_write_exr(output, film, vbl_scene_path(scene), &options, store_half);
    if (wr) {
        exit_code = vbl_cli_fail(wr);
    } else if (preview && !vbl_write_preview(preview, film)) {
        fprintf(stderr, "vbl: cannot write the preview '%s'\n", preview);
        exit_code = VBL_EXIT_IO;
    }
    if (!wr && !cli.quiet) {
        vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
        vbl_film_get_stats(film, &stats);
        fprintf(stderr, "vbl render: wrote %s (%d passes, %.2f s, %d threads)\n", output, stats.passes,
                stats.render_seconds, stats.threads);
    }
    vbl_film_release(film);
    vbl_scene_release(scene);
    return exit_code;
#endif
}

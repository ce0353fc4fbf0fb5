/* `vbl diff A.exr B.exr`: per-layer error of image A against the reference B (rMAE, RMSE, max
 * abs error) over the layers both files have (image_metrics.h computes the numbers). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "image_metrics.h"

#if __has_include("vbl_exr.h")
#include "vbl_exr.h"
#define VBL_DIFF_HAVE_EXR 1
#endif

static void vbl_diff_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl diff A.exr B.exr [--layer NAME] [--json]\n\n"
            "Compares image A against the reference B, layer by layer, over the layers and channels\n"
            "both files have (beauty, emission, volume_direct, volume_from_volume, ...). Prints per\n"
            "layer: rMAE = mean over pixels and channels of |A-B| / (|B| + 0.01 mean|B|), RMSE,\n"
            "the maximum absolute error and the number of pixels. Files of different sizes or with\n"
            "no common layer are refused (exit 3).\n\n"
            "options:\n"
            "  --layer NAME   compare only this layer (\"\" or \"beauty\" for the beauty)\n"
            "  --json         print one JSON object instead of the table\n"
            "  -h, --help     this help\n");
}

#ifdef VBL_DIFF_HAVE_EXR

#define VBL_DIFF_MAX_CHANNELS 64

/* Layer of a full channel name: the part before the last '.', "" for unprefixed channels. */
static size_t vbl_diff_layer_length(const char* channel)
{
    const char* dot = strrchr(channel, '.');
    return dot ? (size_t)(dot - channel) : 0;
}

static void vbl_diff_json_string(FILE* out, const char* s)
{
    fputc('"', out);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(out, "\\%c", c);
        else if (c < 0x20) fprintf(out, "\\u%04x", c);
        else fputc(c, out);
    }
    fputc('"', out);
}

static int vbl_diff_read(const char* path, vbl_exr_image** out)
{
    vbl_result r = vbl_exr_read(path, out);
    if (r != VBL_SUCCESS) {
        const char* message = vbl_last_error_message();
        fprintf(stderr, "vbl diff: cannot read %s: %s\n", path,
                message && message[0] ? message : vbl_result_name(r));
        return r == VBL_ERROR_FILE_IO ? VBL_EXIT_BAD_INPUT : vbl_cli_exit_code(r);
    }
    return VBL_EXIT_OK;
}

typedef struct vbl_diff_layer {
    char name[256];
    int channels;
    const char* channel_names[VBL_DIFF_MAX_CHANNELS]; /* full names, from A */
    vbl_image_metrics metrics;
} vbl_diff_layer;

static int vbl_diff_run(const char* path_a, const char* path_b, const char* only_layer, int json)
{
    vbl_exr_image *a = NULL, *b = NULL;
    int code = vbl_diff_read(path_a, &a);
    if (code == VBL_EXIT_OK) code = vbl_diff_read(path_b, &b);
    if (code != VBL_EXIT_OK) {
        if (a) vbl_exr_image_release(a);
        return code;
    }
    int w = vbl_exr_image_width(a), h = vbl_exr_image_height(a);
    int wb = vbl_exr_image_width(b), hb = vbl_exr_image_height(b);
    vbl_diff_layer* layers = NULL;
    int layer_count = 0;
    if (w != wb || h != hb) {
        fprintf(stderr, "vbl diff: %s is %dx%d but the reference %s is %dx%d: sizes differ\n", path_a, w, h,
                path_b, wb, hb);
        code = VBL_EXIT_BAD_INPUT;
        goto done;
    }
    int channel_count = vbl_exr_image_channel_count(a);
    layers = calloc((size_t)(channel_count > 0 ? channel_count : 1), sizeof *layers);
    if (!layers) {
        fprintf(stderr, "vbl diff: out of memory\n");
        code = VBL_EXIT_FAILURE;
        goto done;
    }
    /* Group A's channels that B also has by layer, in A's channel order. */
    for (int i = 0; i < channel_count; ++i) {
        const char* name = vbl_exr_image_channel_name(a, i);
        if (!name || vbl_exr_image_find_channel(b, name) < 0) continue;
        size_t n = vbl_diff_layer_length(name);
        if (n >= sizeof layers[0].name) continue;
        char layer[256];
        memcpy(layer, name, n);
        layer[n] = 0;
        if (only_layer && strcmp(layer, only_layer)) continue;
        int k = 0;
        while (k < layer_count && strcmp(layers[k].name, layer)) ++k;
        if (k == layer_count) {
            snprintf(layers[k].name, sizeof layers[k].name, "%s", layer);
            ++layer_count;
        }
        if (layers[k].channels < VBL_DIFF_MAX_CHANNELS) layers[k].channel_names[layers[k].channels++] = name;
    }
    if (layer_count == 0) {
        if (only_layer)
            fprintf(stderr, "vbl diff: layer '%s' is not in both %s and %s\n", only_layer, path_a, path_b);
        else
            fprintf(stderr, "vbl diff: %s and %s have no layer (channel) in common\n", path_a, path_b);
        code = VBL_EXIT_BAD_INPUT;
        goto done;
    }
    for (int k = 0; k < layer_count; ++k) {
        const float* pa[VBL_DIFF_MAX_CHANNELS];
        const float* pb[VBL_DIFF_MAX_CHANNELS];
        for (int c = 0; c < layers[k].channels; ++c) {
            pa[c] = vbl_exr_image_channel_pixels(a, vbl_exr_image_find_channel(a, layers[k].channel_names[c]));
            pb[c] = vbl_exr_image_channel_pixels(b, vbl_exr_image_find_channel(b, layers[k].channel_names[c]));
        }
        vbl_image_metrics_compute(pa, pb, layers[k].channels, (size_t)w * (size_t)h, 1, &layers[k].metrics);
    }
    if (json) {
        printf("{\"a\": ");
        vbl_diff_json_string(stdout, path_a);
        printf(", \"b\": ");
        vbl_diff_json_string(stdout, path_b);
        printf(", \"width\": %d, \"height\": %d, \"layers\": [", w, h);
        for (int k = 0; k < layer_count; ++k) {
            const vbl_image_metrics* m = &layers[k].metrics;
            printf("%s\n  {\"name\": ", k ? "," : "");
            vbl_diff_json_string(stdout, layers[k].name);
            printf(", \"channels\": [");
            for (int c = 0; c < layers[k].channels; ++c) {
                if (c) printf(", ");
                vbl_diff_json_string(stdout, layers[k].channel_names[c] + vbl_diff_layer_length(layers[k].channel_names[c]) +
                                                 (vbl_diff_layer_length(layers[k].channel_names[c]) ? 1 : 0));
            }
            printf("], \"pixels\": %zu, \"rmae\": %.17g, \"rmse\": %.17g, \"max_abs\": %.17g, "
                   "\"mean_abs_reference\": %.17g, \"non_finite\": %zu}",
                   m->pixels, m->rmae, m->rmse, m->max_abs, m->mean_abs_ref, m->non_finite);
        }
        printf("\n]}\n");
    } else {
        printf("A: %s\nB: %s (reference)\nsize: %dx%d\n", path_a, path_b, w, h);
        printf("%-24s %4s %10s %14s %14s %14s\n", "layer", "ch", "pixels", "rMAE", "RMSE", "max_abs");
        for (int k = 0; k < layer_count; ++k) {
            const vbl_image_metrics* m = &layers[k].metrics;
            printf("%-24s %4d %10zu %14.8g %14.8g %14.8g\n", layers[k].name[0] ? layers[k].name : "beauty",
                   layers[k].channels, m->pixels, m->rmae, m->rmse, m->max_abs);
            if (m->non_finite)
                printf("  (%s: %zu non-finite values left out)\n", layers[k].name[0] ? layers[k].name : "beauty",
                       m->non_finite);
        }
    }
done:
    free(layers);
    vbl_exr_image_release(a);
    vbl_exr_image_release(b);
    return code;
}
#endif

int vbl_cmd_diff(int argc, char** argv)
{
    const char* paths[2] = {NULL, NULL};
    int path_count = 0, json = 0;
    const char* layer = NULL;
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            vbl_diff_usage(stdout);
            return VBL_EXIT_OK;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if (!strcmp(arg, "--layer")) {
            if (++i >= argc) {
                fprintf(stderr, "vbl diff: --layer needs a layer name\n");
                return VBL_EXIT_USAGE;
            }
            layer = argv[i];
            if (!strcmp(layer, "beauty")) layer = "";
        } else if (arg[0] == '-' && arg[1]) {
            fprintf(stderr, "vbl diff: unknown option '%s'\n", arg);
            vbl_diff_usage(stderr);
            return VBL_EXIT_USAGE;
        } else if (path_count < 2) {
            paths[path_count++] = arg;
        } else {
            fprintf(stderr, "vbl diff: unexpected argument '%s' (two files expected)\n", arg);
            return VBL_EXIT_USAGE;
        }
    }
    if (path_count != 2) {
        vbl_diff_usage(stderr);
        return VBL_EXIT_USAGE;
    }
#ifdef VBL_DIFF_HAVE_EXR
    return vbl_diff_run(paths[0], paths[1], layer, json);
#else
    (void)json;
    (void)layer;
    fprintf(stderr, "vbl diff: this build has no EXR support\n");
    return VBL_EXIT_FAILURE;
#endif
}

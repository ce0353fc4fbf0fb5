/* `vbl preview IN.exr -o OUT.png [--layer NAME] [--display D] [--view V] [--exposure E]
 * [--input-space S] [--config FILE]`: an 8-bit PNG of one EXR layer through an OpenColorIO
 * display/view transform (docs/readme/output.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#if __has_include("vbl_exr.h") && __has_include("vbl_color.h") && defined(VBL_CLI_HAVE_COLOR)
#include "vbl_color.h"
#include "vbl_exr.h"

static void vbl_preview_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl preview IN.exr -o OUT.png [options]\n\n"
            "Writes an 8-bit PNG of one layer of an EXR through an OpenColorIO display/view transform.\n"
            "The config is $OCIO if set, else libvbl's own (displays sRGB and Rec.709, views Standard, Raw).\n\n"
            "  -o, --output OUT.png   output PNG (written to a temporary name, then renamed)\n"
            "  --layer NAME           layer to show: \"\" or beauty (default), emission, volume_direct, ...;\n"
            "                         a one-channel layer (Z, samples) is shown as grey\n"
            "  --display NAME         OCIO display (default: the config's default, sRGB)\n"
            "  --view NAME            OCIO view of the display (default: the display's default, Standard)\n"
            "  --exposure STOPS       exposure adjustment in stops before the view transform (default 0)\n"
            "  --input-space NAME     colour space of the EXR's pixels (default: the file's oiio:ColorSpace\n"
            "                         attribute if the config knows it, else the role scene_linear)\n"
            "  --config FILE          OCIO config to use instead of $OCIO / the built-in one\n"
            "  -h, --help             this help\n\n"
            "Exit status: 0 ok, 2 bad command line or unknown layer/space/display/view, 3 missing or corrupt\n"
            "input or config, 4 cannot write the output.\n");
}

/* Gathers the RGB (or grey) pixels of `layer` from the image; reports an error listing the layers. */
static vbl_result vbl_preview_gather(const vbl_exr_image* img, const char* path, const char* layer, float** out)
{
    const int n = vbl_exr_image_width(img) * vbl_exr_image_height(img);
    const char* prefix = layer && strcmp(layer, "beauty") ? layer : "";
    int idx[3] = {-1, -1, -1};
    static const char* const rgb[3] = {"R", "G", "B"};
    char name[300];
    for (int c = 0; c < 3; ++c) {
        snprintf(name, sizeof name, "%s%s%s", prefix, prefix[0] ? "." : "", rgb[c]);
        idx[c] = vbl_exr_image_find_channel(img, name);
    }
    if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) {
        /* A one-channel layer: "Z", or "<layer>.<single channel>". */
        int single = prefix[0] ? vbl_exr_image_find_channel(img, prefix) : -1;
        size_t len = strlen(prefix);
        int matches = 0;
        for (int i = 0; single < 0 && prefix[0] && i < vbl_exr_image_channel_count(img); ++i) {
            const char* ch = vbl_exr_image_channel_name(img, i);
            if (!strncmp(ch, prefix, len) && ch[len] == '.' && !strchr(ch + len + 1, '.')) {
                ++matches;
                idx[0] = i;
            }
        }
        if (single < 0 && matches == 1) single = idx[0];
        if (single < 0) {
            char list[1024] = "";
            size_t used = 0;
            for (int i = 0; i < vbl_exr_image_channel_count(img) && used + 2 < sizeof list; ++i)
                used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", vbl_exr_image_channel_name(img, i));
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: no layer '%s' with R,G,B or a single channel (channels: %s)",
                                    path, prefix[0] ? prefix : "(beauty)", list);
        }
        idx[0] = idx[1] = idx[2] = single;
    }
    float* px = malloc(sizeof(float) * 3 * (size_t)n);
    if (!px) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (int c = 0; c < 3; ++c) {
        const float* src = vbl_exr_image_channel_pixels(img, idx[c]);
        for (int i = 0; i < n; ++i) px[(size_t)i * 3 + (size_t)c] = src[i];
    }
    *out = px;
    return VBL_SUCCESS;
}

int vbl_cmd_preview(int argc, char** argv)
{
    const char *input = NULL, *output = NULL, *layer = NULL, *config_path = NULL;
    vbl_preview_options opt = VBL_PREVIEW_OPTIONS_DEFAULT;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            vbl_preview_usage(stdout);
            return VBL_EXIT_OK;
        }
        int takes_value = !strcmp(a, "-o") || !strcmp(a, "--output") || !strcmp(a, "--layer") || !strcmp(a, "--display") ||
                          !strcmp(a, "--view") || !strcmp(a, "--exposure") || !strcmp(a, "--input-space") ||
                          !strcmp(a, "--config");
        if (takes_value) {
            if (i + 1 >= argc) {
                fprintf(stderr, "vbl preview: %s needs a value\n", a);
                return VBL_EXIT_USAGE;
            }
            const char* v = argv[++i];
            if (!strcmp(a, "-o") || !strcmp(a, "--output")) output = v;
            else if (!strcmp(a, "--layer")) layer = v;
            else if (!strcmp(a, "--display")) opt.display = v;
            else if (!strcmp(a, "--view")) opt.view = v;
            else if (!strcmp(a, "--input-space")) opt.input_space = v;
            else if (!strcmp(a, "--config")) config_path = v;
            else {
                char* end = NULL;
                double e = strtod(v, &end);
                if (!end || *end || end == v || !isfinite(e) || fabs(e) > 64.0) {
                    fprintf(stderr, "vbl preview: --exposure '%s' is not a number of stops in [-64, 64]\n", v);
                    return VBL_EXIT_USAGE;
                }
                opt.exposure = (float)e;
            }
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vbl preview: unknown option '%s' (see 'vbl preview --help')\n", a);
            return VBL_EXIT_USAGE;
        } else if (!input) {
            input = a;
        } else {
            fprintf(stderr, "vbl preview: unexpected argument '%s'\n", a);
            return VBL_EXIT_USAGE;
        }
    }
    if (!input || !output) {
        vbl_preview_usage(stderr);
        return VBL_EXIT_USAGE;
    }
    vbl_color_config* config = NULL;
    vbl_result r = vbl_color_config_open(config_path, &config);
    if (r != VBL_SUCCESS) return vbl_cli_fail(r);
    vbl_exr_image* img = NULL;
    r = vbl_exr_read(input, &img);
    float* px = NULL;
    if (r == VBL_SUCCESS) r = vbl_preview_gather(img, input, layer, &px);
    if (r == VBL_SUCCESS && !opt.input_space) {
        const char* tagged = vbl_exr_image_attribute(img, "oiio:ColorSpace", NULL);
        const char* resolved = NULL;
        if (tagged && vbl_color_resolve_space(config, tagged, &resolved) == VBL_SUCCESS) opt.input_space = resolved;
        else if (tagged) fprintf(stderr, "vbl preview: %s: colour space '%s' is not in the config; assuming scene_linear\n", input, tagged);
        vbl_clear_error();
    }
    if (r == VBL_SUCCESS) {
        opt.config = config;
        r = vbl_preview_write_png(output, px, vbl_exr_image_width(img), vbl_exr_image_height(img), 3, &opt);
    }
    free(px);
    vbl_exr_image_release(img);
    vbl_color_config_release(config);
    return r == VBL_SUCCESS ? VBL_EXIT_OK : vbl_cli_fail(r);
}

#else

int vbl_cmd_preview(int argc, char** argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "vbl preview: this build has no OpenColorIO/OpenEXR support\n");
    return VBL_EXIT_FAILURE;
}

#endif

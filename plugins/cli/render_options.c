/* `vbl render` flag parsing and --help text (docs/readme/render.md, "Command line"). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "options_doc.h"
#include "render_cli.h"

static void vbl_render_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl render SCENE.json -o OUT.exr [options]\n\n"
            "Renders a scene file (README 'Rendering') to one multi-layer OpenEXR: beauty R,G,B,A and one\n"
            "layer per light-transport class the scene produces (background, volume_direct, volume_from_volume),\n"
            "which sum to the beauty exactly in FLOAT storage. Options override the scene's \"render\" block.\n\n"
            "  -o, --output OUT.exr       output EXR (written to a temporary name, then renamed)\n"
            "  --vdb PATH                 replace media[i].vdb (i-th use -> media[i]); for sample scenes\n"
            "  --camera NAME|FILE.json    render through the scene's cameras.NAME, or a camera in a JSON file\n"
            "  --resolution WxH           image size instead of the camera's (the lens keeps its fov / fit)\n"
            "  --transparent on           keep the background (sky, visible lights) out of the beauty: a\n"
            "                             premultiplied element over A (the background layer still holds it)\n"
            "  --animated-seed            with --frames: frame f uses seed + f * 0x9E3779B97F4A7C15 (noise\n"
            "                             that changes per frame instead of a fixed pattern)\n"
            "  Flags take their value as '--flag VALUE' or '--flag=VALUE'.\n\n"
            "Render options (the scene's \"render\" keys; 'vbl options --markdown' is the docs table):\n");
    vbl_options_doc_help(out);
    fprintf(out,
            "\n"
            "Output file:\n"
            "  --aov LIST                 extra layers, comma-separated: z, samples, variance, all\n"
            "  --half                     store beauty, transport and variance layers as HALF (default FLOAT;\n"
            "                             HALF layers no longer sum to the beauty exactly). Z, samples: FLOAT\n"
            "  --half-layers LIST         only these layers as HALF (beauty, background, volume_direct, ...)\n"
            "  --compression NAME         none|zip|piz|dwaa (default zip)\n"
            "  --tiled                    tiled EXR (default scanlines); --tile-size N (default 64)\n"
            "  --checkpoint-passes N      rewrite OUT.exr every N passes while rendering\n"
            "  --checkpoint-seconds S     rewrite OUT.exr when S seconds passed since the last write\n\n"
            "Colour (OpenColorIO; config $OCIO, else libvbl's own):\n"
            "  --output-space NAME        colour space of the EXR pixels (default: the role scene_linear)\n"
            "  --config FILE              OCIO config instead of $OCIO / the built-in one\n"
            "  --preview OUT.png          also write an 8-bit PNG of the beauty through a display/view\n"
            "  --display NAME, --view NAME, --exposure STOPS   the preview's transform (defaults: the\n"
            "                             config's default display and view, 0 stops)\n\n"
            "Pipelines (README 'Pipeline adapters'):\n"
            "  --preset NAME              preview|production|final, applied after the scene's render block and\n"
            "                             before the flags above\n"
            "  --frames SPEC              render frames: 5, 1-10, 1-100x2, 1,3,7; '####' or '%%04d' in the scene's\n"
            "                             media[i].vdb, --vdb, -o and --preview become the frame number\n"
            "  --keep-going               with --frames: a failed frame does not stop the later ones (the exit\n"
            "                             code is still non-zero)\n"
            "  --pass-range A-B           render only the absolute passes A..B (inclusive, 0-based) with the seeds\n"
            "                             of a single render; combine the parts with 'vbl merge'\n"
            "  --resume                   if OUT.exr is a checkpoint of this render, render only the passes left\n"
            "                             and merge them into it (no OUT.exr: render from the start)\n"
            "  --progress MODE            auto (a bar if stderr is a terminal, else lines), bar, lines, none, or\n"
            "                             json: one JSON object per line on stdout\n"
            "  -q, --quiet                no progress (--progress none)\n"
            "  -h, --help                 this text\n\n"
            "Exit codes: 0 ok, 1 render failed, 2 bad command line or unknown colour space, 3 bad scene/VDB or\n"
            "incompatible checkpoint, 4 cannot write, 5 interrupted (SIGINT/SIGTERM: the passes done so far are\n"
            "still written; --resume continues them).\n");
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

static int vbl_parse_double(const char* text, double min, double max, double* out)
{
    char* end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || !end || *end || end == text || !isfinite(v) || v < min || v > max) return 0;
    *out = v;
    return 1;
}

/* --pass-range A-B: 0 <= A <= B. */
static int vbl_parse_pass_range(const char* text, long* first, long* last)
{
    const char* dash = strchr(text, '-');
    if (!dash || dash == text) return 0;
    char a[32];
    size_t n = (size_t)(dash - text);
    if (n >= sizeof a) return 0;
    memcpy(a, text, n);
    a[n] = 0;
    return vbl_parse_long(a, 0, INT_MAX - 1, first) && vbl_parse_long(dash + 1, 0, INT_MAX - 1, last) &&
           *last >= *first;
}

/* --resolution WxH: two integers in [1, 32768] ("1920x1080"). */
static int vbl_parse_resolution(const char* text, int* width, int* height)
{
    const char* x = strchr(text, 'x');
    if (!x) x = strchr(text, 'X');
    if (!x || x == text) return 0;
    char a[32];
    size_t n = (size_t)(x - text);
    if (n >= sizeof a) return 0;
    memcpy(a, text, n);
    a[n] = 0;
    long w = 0, h = 0;
    if (!vbl_parse_long(a, 1, 32768, &w) || !vbl_parse_long(x + 1, 1, 32768, &h)) return 0;
    *width = (int)w;
    *height = (int)h;
    return 1;
}

static int vbl_parse_compression(const char* text, int* out)
{
    static const char* const names[4] = {"none", "zip", "piz", "dwaa"};
    for (int i = 0; i < 4; ++i)
        if (!strcmp(text, names[i])) {
            *out = i; /* vbl_exr_compression order */
            return 1;
        }
    return 0;
}

/* --aov LIST: comma-separated z, samples, variance, all. */
static int vbl_parse_aovs(const char* text, vbl_render_args* args)
{
    const char* p = text;
    while (*p) {
        size_t n = strcspn(p, ",");
        if (n == 1 && !strncmp(p, "z", 1)) args->aov_z = 1;
        else if (n == 1 && !strncmp(p, "Z", 1)) args->aov_z = 1;
        else if (n == 7 && !strncmp(p, "samples", 7)) args->aov_samples = 1;
        else if (n == 8 && !strncmp(p, "variance", 8)) args->aov_variance = 1;
        else if (n == 3 && !strncmp(p, "all", 3)) args->aov_z = args->aov_samples = args->aov_variance = 1;
        else return 0;
        p += n;
        if (*p == ',') ++p;
    }
    return 1;
}

int vbl_render_parse_args(int argc, char** argv, vbl_render_args* args)
{
    memset(args, 0, sizeof *args);
    args->compression = -1;
    if (vbl_render_option_count() > VBL_RENDER_CLI_MAX_OPTIONS) {
        fprintf(stderr, "vbl render: %d render options, more than VBL_RENDER_CLI_MAX_OPTIONS\n",
                vbl_render_option_count());
        return VBL_EXIT_FAILURE;
    }
    args->pass_first = args->pass_last = -1;

    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = 1, ok = 1, option = -1, inline_value = 0;
        char flag[128];
        const char* eq = a[0] == '-' && a[1] == '-' ? strchr(a, '=') : NULL;
        if (eq) { /* getopt_long's --flag=value */
            size_t n = (size_t)(eq - a);
            if (n >= sizeof flag) {
                fprintf(stderr, "vbl render: unknown option '%s' (see 'vbl render --help')\n", a);
                return VBL_EXIT_USAGE;
            }
            memcpy(flag, a, n);
            flag[n] = 0;
            a = flag;
            v = eq + 1;
            inline_value = 1;
        }
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            vbl_render_usage(stdout);
            return VBL_EXIT_OK;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            args->quiet = 1;
            args->progress_mode = VBL_PROGRESS_NONE;
            takes = 0;
        } else if (!strcmp(a, "--resume")) {
            args->resume = 1;
            takes = 0;
        } else if (!strcmp(a, "--keep-going")) {
            args->keep_going = 1;
            takes = 0;
        } else if (!strcmp(a, "--half")) {
            args->half_all = 1;
            takes = 0;
        } else if (!strcmp(a, "--tiled")) {
            args->tiled = 1;
            takes = 0;
        } else if (!strcmp(a, "--animated-seed")) {
            args->animated_seed = 1;
            takes = 0;
        } else if (a[0] != '-' || !a[1]) {
            if (args->scene_path) {
                fprintf(stderr, "vbl render: more than one scene file ('%s', '%s')\n", args->scene_path, a);
                return VBL_EXIT_USAGE;
            }
            args->scene_path = a;
            takes = 0;
        } else if (!v) {
            fprintf(stderr, "vbl render: %s needs a value (see 'vbl render --help')\n", a);
            return VBL_EXIT_USAGE;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) args->output = v;
        else if (!strcmp(a, "--preview")) args->preview = v;
        else if ((option = vbl_render_option_find(a)) >= 0 && vbl_render_option_desc(option)->flag &&
                 !strcmp(vbl_render_option_desc(option)->flag, a)) {
            /* the library's validator, as scene files use it */
            vbl_render_options probe = VBL_RENDER_OPTIONS_DEFAULT;
            if (vbl_render_option_set_strict(&probe, vbl_render_option_desc(option)->name, v)) {
                fprintf(stderr, "vbl render: invalid value '%s' for %s: %s (see 'vbl render --help')\n", v, a,
                        vbl_last_error_message());
                vbl_clear_error();
                return VBL_EXIT_USAGE;
            }
            args->option_values[option] = v;
        }
        else if (!strcmp(a, "--aov")) ok = vbl_parse_aovs(v, args), args->aovs = v;
        else if (!strcmp(a, "--camera")) args->camera = v;
        else if (!strcmp(a, "--resolution")) ok = vbl_parse_resolution(v, &args->width, &args->height);
        else if (!strcmp(a, "--half-layers")) args->half_layers = v;
        else if (!strcmp(a, "--compression")) ok = vbl_parse_compression(v, &args->compression);
        else if (!strcmp(a, "--tile-size")) {
            long t = 0;
            ok = vbl_parse_long(v, 1, 65536, &t);
            args->tile_size = (int)t;
        } else if (!strcmp(a, "--output-space")) args->output_space = v;
        else if (!strcmp(a, "--config")) args->config = v;
        else if (!strcmp(a, "--display")) args->display = v;
        else if (!strcmp(a, "--view")) args->view = v;
        else if (!strcmp(a, "--exposure")) ok = vbl_parse_double(v, -64.0, 64.0, &args->exposure);
        else if (!strcmp(a, "--preset")) args->preset = v;
        else if (!strcmp(a, "--frames")) args->frames = v;
        else if (!strcmp(a, "--pass-range")) ok = vbl_parse_pass_range(v, &args->pass_first, &args->pass_last);
        else if (!strcmp(a, "--progress")) {
            vbl_progress_mode mode = VBL_PROGRESS_AUTO;
            ok = vbl_progress_parse(v, &mode);
            if (ok && !args->quiet) args->progress_mode = (int)mode;
        } else if (!strcmp(a, "--checkpoint-passes")) ok = vbl_parse_long(v, 1, INT_MAX, &args->checkpoint_passes);
        else if (!strcmp(a, "--checkpoint-seconds"))
            ok = vbl_parse_double(v, 0.0, 1e12, &args->checkpoint_seconds) && args->checkpoint_seconds > 0.0;
        else if (!strcmp(a, "--vdb")) {
            if (args->vdb_count >= VBL_RENDER_CLI_MAX_VDB) {
                fprintf(stderr, "vbl render: at most %d --vdb overrides\n", VBL_RENDER_CLI_MAX_VDB);
                return VBL_EXIT_USAGE;
            }
            args->vdb[args->vdb_count++] = v;
        } else {
            fprintf(stderr, "vbl render: unknown option '%s' (see 'vbl render --help')\n", a);
            return VBL_EXIT_USAGE;
        }
        if (!ok) {
            fprintf(stderr, "vbl render: invalid value '%s' for %s (see 'vbl render --help')\n", v, a);
            return VBL_EXIT_USAGE;
        }
        if (inline_value && !takes) {
            fprintf(stderr, "vbl render: %s takes no value (got '%s')\n", a, v);
            return VBL_EXIT_USAGE;
        }
        i += inline_value ? 0 : takes;
    }
    if (!args->scene_path || !args->output) {
        fprintf(stderr, "vbl render: %s\n\n", !args->scene_path ? "no scene file given" : "no output given (-o OUT.exr)");
        vbl_render_usage(stderr);
        return VBL_EXIT_USAGE;
    }
    const char* passes_text = args->option_values[vbl_render_option_find("passes")];
    long passes = passes_text ? atol(passes_text) : -1;
    if (args->pass_first >= 0 && passes > 0 && args->pass_last >= passes) {
        fprintf(stderr, "vbl render: --pass-range %ld-%ld goes past --passes %ld (passes are 0..%ld)\n",
                args->pass_first, args->pass_last, passes, passes - 1);
        return VBL_EXIT_USAGE;
    }
    if (args->keep_going && !args->frames) {
        fprintf(stderr, "vbl render: --keep-going needs --frames\n");
        return VBL_EXIT_USAGE;
    }
    if (args->animated_seed && !args->frames) {
        fprintf(stderr, "vbl render: --animated-seed needs --frames\n");
        return VBL_EXIT_USAGE;
    }
    if (args->tile_size && !args->tiled) {
        fprintf(stderr, "vbl render: --tile-size needs --tiled\n");
        return VBL_EXIT_USAGE;
    }
    return -1;
}

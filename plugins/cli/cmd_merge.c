/* `vbl merge OUT.exr IN.exr...`: combines EXRs of disjoint pass ranges of one render
 * (`vbl render --pass-range`, farm tasks, checkpoints) into the EXR one process rendering all of
 * those passes would have written, within float rounding (docs/readme/pipeline.md, "Split and
 * merge"). Per-channel rules: merge.h; the inputs are read one at a time into double running sums,
 * so memory holds the first input, the current one and the sums, whatever the input count. */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "exr_film.h"
#include "merge.h"

#define VBL_MERGE_MAX_INPUTS 4096
#define VBL_MERGE_MAX_CHANNELS 64

static void vbl_merge_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl merge OUT.exr IN1.exr IN2.exr ... [--allow-gaps] [-q]\n\n"
            "Combines EXRs of disjoint pass ranges of the same render (vbl render --pass-range A-B, farm\n"
            "tasks, checkpoints) into one EXR, as if one process had rendered all their passes: colour\n"
            "layers and A are averaged weighted by pass count, samples are summed, variance (of the mean)\n"
            "combines as sum (n_i/N)^2 var_i, Z is weighted by n_i * A_i, and the beauty R,G,B is recomputed\n"
            "as the sum of the transport layers (so the layers still sum to the beauty exactly).\n"
            "Refused (exit 3, naming the file): different scene hash, media, frame, method, seed, spp,\n"
            "light paths, render settings, colour space, resolution or channels; overlapping pass\n"
            "ranges; a gap in the passes (passes 0..N-1 not all present) unless --allow-gaps.\n\n"
            "  --allow-gaps   merge ranges with missing passes (an unbiased image of fewer passes, but not\n"
            "                 what a single render would give; vbl:status = \"partial\")\n"
            "  -q, --quiet    no summary on stderr\n"
            "  -h, --help     this text\n\n"
            "Exit codes: 0 ok, 2 bad command line, 3 unreadable or incompatible inputs, 4 cannot write OUT.\n");
}

typedef struct vbl_merge_input {
    const char* path;
    vbl_exr_image* image;
    int passes, first_pass, requested;
    int complete;
    double seconds;
} vbl_merge_input;

static int vbl_merge_by_first_pass(const void* a, const void* b)
{
    const vbl_merge_input* x = a;
    const vbl_merge_input* y = b;
    return (x->first_pass > y->first_pass) - (x->first_pass < y->first_pass);
}

static int vbl_merge_attr_int(const vbl_exr_image* image, const char* name, int* out)
{
    const char* text = vbl_exr_image_attribute(image, name, NULL);
    if (!text) return 0;
    char* end = NULL;
    long v = strtol(text, &end, 10);
    if (!end || *end || end == text || v < 0 || v > 0x7fffffffL) return 0;
    *out = (int)v;
    return 1;
}

/* The pass count a file claims against what else it records (a part claiming 200 passes re-weighted
 * the merge): its vbl:pass_range A-B (first_pass = A, passes = B-A+1, or fewer if interrupted) and
 * its samples channel (passes x spp camera samples in every pixel). Returns an exit code. */
static int vbl_merge_check_counts(const vbl_merge_input* in)
{
    const char* range = vbl_exr_image_attribute(in->image, "vbl:pass_range", NULL);
    long long a = 0, b = 0;
    char tail = 0;
    if (range && sscanf(range, "%lld-%lld%c", &a, &b, &tail) == 2) {
        const long long span = b - a + 1;
        if (a != in->first_pass || span < 1 || in->passes > span || (in->complete && in->passes != span)) {
            fprintf(stderr,
                    "vbl merge: %s: vbl:passes = %d and vbl:first_pass = %d do not fit its vbl:pass_range %lld-%lld "
                    "(%s)\n",
                    in->path, in->passes, in->first_pass, a, b, in->complete ? "complete" : "partial");
            return VBL_EXIT_BAD_INPUT;
        }
    }
    int spp = 0;
    const int c = vbl_exr_image_find_channel(in->image, "samples.Y");
    if (c >= 0 && vbl_merge_attr_int(in->image, "vbl:spp", &spp) && spp > 0) {
        const float* samples = vbl_exr_image_channel_pixels(in->image, c);
        const size_t n = (size_t)vbl_exr_image_width(in->image) * (size_t)vbl_exr_image_height(in->image);
        const double want = (double)in->passes * (double)spp;
        for (size_t i = 0; i < n; ++i)
            if ((double)samples[i] != want) {
                fprintf(stderr,
                        "vbl merge: %s: vbl:passes = %d with vbl:spp = %d means %.0f samples per pixel, but samples.Y "
                        "is %.9g at pixel %zu\n",
                        in->path, in->passes, spp, want, (double)samples[i], i);
                return VBL_EXIT_BAD_INPUT;
            }
    }
    return VBL_EXIT_OK;
}

/* Reads and checks one input against the first. Returns an exit code (0: fine). */
static int vbl_merge_open(vbl_merge_input* in, const vbl_merge_input* first, const vbl_merge_identity* first_id)
{
    vbl_result r = vbl_exr_read(in->path, &in->image);
    if (r) {
        const char* m = vbl_last_error_message();
        fprintf(stderr, "vbl merge: cannot read %s: %s\n", in->path, m && m[0] ? m : vbl_result_name(r));
        return VBL_EXIT_BAD_INPUT;
    }
    if (!vbl_merge_attr_int(in->image, "vbl:passes", &in->passes) || in->passes < 1 ||
        !vbl_merge_attr_int(in->image, "vbl:first_pass", &in->first_pass)) {
        fprintf(stderr,
                "vbl merge: %s: no vbl:passes / vbl:first_pass metadata (not a vbl render, or one written before "
                "split rendering)\n",
                in->path);
        return VBL_EXIT_BAD_INPUT;
    }
    if (!vbl_merge_attr_int(in->image, "vbl:passes_requested", &in->requested)) in->requested = in->passes;
    const char* status = vbl_exr_image_attribute(in->image, "vbl:status", NULL);
    in->complete = status && !strcmp(status, "complete");
    const char* seconds = vbl_exr_image_attribute(in->image, "vbl:render_seconds", NULL);
    in->seconds = seconds ? atof(seconds) : 0.0;
    int counts = vbl_merge_check_counts(in);
    if (counts != VBL_EXIT_OK) return counts;
    if (!first) return VBL_EXIT_OK;
    vbl_merge_identity id;
    vbl_merge_identity_from_image(in->image, &id);
    char msg[4096];
    if (vbl_merge_identity_compare(first_id, first->path, &id, in->path, msg, sizeof msg)) {
        fprintf(stderr, "vbl merge: %s: not the same render\n", msg);
        return VBL_EXIT_BAD_INPUT;
    }
    int n0 = vbl_exr_image_channel_count(first->image), n1 = vbl_exr_image_channel_count(in->image);
    for (int c = 0; c < n0; ++c)
        if (vbl_exr_image_find_channel(in->image, vbl_exr_image_channel_name(first->image, c)) < 0) {
            fprintf(stderr, "vbl merge: %s has no channel '%s' but %s has (render the parts with the same --aov)\n",
                    in->path, vbl_exr_image_channel_name(first->image, c), first->path);
            return VBL_EXIT_BAD_INPUT;
        }
    if (n1 != n0) {
        for (int c = 0; c < n1; ++c)
            if (vbl_exr_image_find_channel(first->image, vbl_exr_image_channel_name(in->image, c)) < 0) {
                fprintf(stderr, "vbl merge: %s has a channel '%s' that %s lacks (render the parts with the same --aov)\n",
                        in->path, vbl_exr_image_channel_name(in->image, c), first->path);
                return VBL_EXIT_BAD_INPUT;
            }
    }
    return VBL_EXIT_OK;
}

/* Layer prefix length of a full channel name ("emission.R" -> 8, "R" -> 0). */
static size_t vbl_merge_prefix(const char* channel)
{
    const char* dot = strrchr(channel, '.');
    return dot ? (size_t)(dot - channel) : 0;
}

typedef struct vbl_merge_out_layer {
    char name[256];
    const char* channel_names[4];
    int channels[4]; /* channel indices in the output planes */
    int count;
    int half;
} vbl_merge_out_layer;

/* What the merged file's header says about its passes (vbl:passes, vbl:first_pass, ...). */
typedef struct vbl_merge_summary {
    int total_passes, first_pass, last_pass, requested;
    const char* status;      /* "complete" or "partial" */
    double seconds;          /* summed render time */
    const char* color_space; /* the inputs' output colour space, or NULL */
} vbl_merge_summary;

static int vbl_merge_write(const char* out_path, const vbl_merge_input* in, int count, float** planes,
                           const vbl_exr_image* first, const vbl_merge_summary* summary)
{
    const int total_passes = summary->total_passes, first_pass = summary->first_pass;
    const int last_pass = summary->last_pass, requested = summary->requested;
    const char* status = summary->status;
    const double seconds = summary->seconds;
    const char* color_space = summary->color_space;
    const int w = vbl_exr_image_width(first), h = vbl_exr_image_height(first);
    const size_t n = (size_t)w * (size_t)h;
    const int channel_count = vbl_exr_image_channel_count(first);
    vbl_merge_out_layer layers[VBL_MERGE_MAX_CHANNELS];
    int layer_count = 0;
    /* beauty R,G,B,A first, Z on its own, then the layers by prefix in channel order */
    static const char* const beauty_names[4] = {"R", "G", "B", "A"};
    vbl_merge_out_layer* beauty = &layers[layer_count++];
    memset(beauty, 0, sizeof *beauty);
    for (int k = 0; k < 4; ++k) {
        int c = vbl_exr_image_find_channel(first, beauty_names[k]);
        if (c < 0) continue;
        beauty->channel_names[beauty->count] = beauty_names[k];
        beauty->channels[beauty->count++] = c;
        beauty->half |= vbl_exr_image_channel_is_half(first, c);
    }
    if (!beauty->count) --layer_count;
    for (int c = 0; c < channel_count; ++c) {
        const char* name = vbl_exr_image_channel_name(first, c);
        size_t p = vbl_merge_prefix(name);
        if (p == 0 && strcmp(name, "Z")) continue; /* R, G, B, A: the beauty */
        char layer[256];
        snprintf(layer, sizeof layer, "%.*s", (int)(p ? p : 1), p ? name : "Z");
        int k = 0;
        while (k < layer_count && (k == 0 && beauty->count ? 1 : strcmp(layers[k].name, layer))) ++k;
        if (k == layer_count) {
            if (layer_count >= VBL_MERGE_MAX_CHANNELS) break;
            memset(&layers[k], 0, sizeof layers[k]);
            snprintf(layers[k].name, sizeof layers[k].name, "%s", layer);
            ++layer_count;
        }
        if (layers[k].count >= 4) {
            fprintf(stderr, "vbl merge: %s: layer '%s' has more than 4 channels\n", in[0].path, layer);
            return VBL_EXIT_BAD_INPUT;
        }
        layers[k].channel_names[layers[k].count] = p ? name + p + 1 : "Z";
        layers[k].channels[layers[k].count++] = c;
        layers[k].half |= vbl_exr_image_channel_is_half(first, c);
    }
    vbl_exr_layer exr_layers[VBL_MERGE_MAX_CHANNELS];
    float* buffers[VBL_MERGE_MAX_CHANNELS] = {NULL};
    int code = VBL_EXIT_OK;
    for (int k = 0; k < layer_count; ++k) {
        vbl_merge_out_layer* l = &layers[k];
        buffers[k] = malloc(sizeof(float) * n * (size_t)l->count);
        if (!buffers[k]) {
            fprintf(stderr, "vbl merge: out of memory\n");
            code = VBL_EXIT_FAILURE;
            break;
        }
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < l->count; ++c) buffers[k][i * (size_t)l->count + (size_t)c] = planes[l->channels[c]][i];
        memset(&exr_layers[k], 0, sizeof exr_layers[k]);
        exr_layers[k].name = (k == 0 && beauty->count) || !strcmp(l->name, "Z") ? "" : l->name;
        exr_layers[k].channel_count = l->count;
        exr_layers[k].channel_names = l->channel_names;
        exr_layers[k].pixels = buffers[k];
        exr_layers[k].store_half = l->half && strcmp(l->name, "Z") && strcmp(l->name, "samples");
    }
    if (code == VBL_EXIT_OK) {
        /* metadata: the first input's, with the pass counts of the merged file */
        static const char* const copied[] = {"software",        "vbl:version",     "vbl:scene",       "vbl:scene_hash",
                                             "vbl:media",       "vbl:frame",       "vbl:method",      "vbl:preset",
                                             "vbl:spp",         "vbl:light_paths", "vbl:seed",        "vbl:options_hash",
                                             "vbl:threads",     "vbl:max_bounces", "vbl:transmittance", "vbl:alpha",
                                             "vbl:scene_color_space", "vbl:transparent", "worldToCamera",
                                             "worldToNDC", NULL};
        vbl_exr_attribute attrs[40];
        float matrices[2][16];
        int attr_count = 0, matrix_count = 0;
        for (int i = 0; copied[i]; ++i) {
            int type = 0;
            const char* v = vbl_exr_image_attribute(first, copied[i], &type);
            if (!v || type < 0) continue;
            vbl_exr_attribute* a = &attrs[attr_count++];
            memset(a, 0, sizeof *a);
            a->name = copied[i];
            a->type = (vbl_exr_attribute_type)type;
            a->value = v;
            a->int_value = atoi(v);
            a->double_value = atof(v);
            if (type == VBL_EXR_ATTRIBUTE_M44F) { /* the 16 numbers of the reader's text */
                if (matrix_count == 2) {
                    --attr_count;
                    continue;
                }
                float* m = matrices[matrix_count++];
                const char* p = v;
                for (int e = 0; e < 16; ++e) {
                    char* end = NULL;
                    m[e] = strtof(p, &end);
                    p = end && end != p ? end : p;
                }
                a->m44 = m;
            }
        }
        char range[64], merged_from[8192];
        snprintf(range, sizeof range, "%d-%d", first_pass, last_pass);
        size_t used = 0;
        merged_from[0] = 0;
        for (int i = 0; i < count && used + 2 < sizeof merged_from; ++i) {
            int m = snprintf(merged_from + used, sizeof merged_from - used, "%s%s", i ? ";" : "", in[i].path);
            if (m < 0) break;
            used += (size_t)m;
            if (used >= sizeof merged_from) used = sizeof merged_from - 1;
        }
        const vbl_exr_attribute extra[] = {
            {"vbl:status", status, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL},
            {"vbl:passes", NULL, VBL_EXR_ATTRIBUTE_INT, total_passes, 0.0, NULL},
            {"vbl:passes_requested", NULL, VBL_EXR_ATTRIBUTE_INT, requested, 0.0, NULL},
            {"vbl:first_pass", NULL, VBL_EXR_ATTRIBUTE_INT, first_pass, 0.0, NULL},
            {"vbl:pass_range", range, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL},
            {"vbl:merged_from", merged_from, VBL_EXR_ATTRIBUTE_STRING, 0, 0.0, NULL},
            {"vbl:render_seconds", NULL, VBL_EXR_ATTRIBUTE_DOUBLE, 0, seconds, NULL},
        };
        for (size_t i = 0; i < sizeof extra / sizeof extra[0]; ++i) attrs[attr_count++] = extra[i];
        vbl_exr_write_options wo = VBL_EXR_WRITE_OPTIONS_DEFAULT;
        wo.attributes = attrs;
        wo.attribute_count = attr_count;
        int compression = (int)vbl_exr_image_compression(first);
        if (compression >= 0) wo.compression = (vbl_exr_compression)compression;
        wo.tiled = vbl_exr_image_tiled(first);
        wo.tile_size = vbl_exr_image_tile_size(first);
        wo.color_space = color_space;
        float chroma[8];
        if (vbl_exr_image_chromaticities(first, chroma)) wo.chromaticities = chroma;
        vbl_result r = vbl_exr_write(out_path, w, h, exr_layers, layer_count, &wo);
        if (r) {
            const char* m = vbl_last_error_message();
            fprintf(stderr, "vbl merge: %s\n", m && m[0] ? m : vbl_result_name(r));
            code = VBL_EXIT_IO;
        }
    }
    for (int k = 0; k < layer_count; ++k) free(buffers[k]);
    return code;
}

int vbl_cmd_merge(int argc, char** argv)
{
    const char* out_path = NULL;
    int allow_gaps = 0, quiet = 0, count = 0;
    vbl_merge_input* in = calloc((size_t)(argc > 1 ? argc : 1), sizeof *in);
    if (!in) return VBL_EXIT_FAILURE;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            vbl_merge_usage(stdout);
            free(in);
            return VBL_EXIT_OK;
        } else if (!strcmp(a, "--allow-gaps")) {
            allow_gaps = 1;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vbl merge: unknown option '%s' (see 'vbl merge --help')\n", a);
            free(in);
            return VBL_EXIT_USAGE;
        } else if (!out_path) {
            out_path = a;
        } else if (count < VBL_MERGE_MAX_INPUTS) {
            in[count++].path = a;
        } else {
            fprintf(stderr, "vbl merge: more than %d inputs\n", VBL_MERGE_MAX_INPUTS);
            free(in);
            return VBL_EXIT_USAGE;
        }
    }
    if (!out_path || count < 1) {
        fprintf(stderr, "vbl merge: %s\n\n", !out_path ? "no output given" : "no input EXR given");
        vbl_merge_usage(stderr);
        free(in);
        return VBL_EXIT_USAGE;
    }

    /* the first input: identity, channels and metadata of the result */
    vbl_merge_identity first_id;
    int code = vbl_merge_open(&in[0], NULL, NULL);
    int channel_count = 0;
    size_t n = 0;
    if (code == VBL_EXIT_OK) {
        vbl_merge_identity_from_image(in[0].image, &first_id);
        channel_count = vbl_exr_image_channel_count(in[0].image);
        n = (size_t)vbl_exr_image_width(in[0].image) * (size_t)vbl_exr_image_height(in[0].image);
        if (channel_count > VBL_MERGE_MAX_CHANNELS) {
            fprintf(stderr, "vbl merge: %s has %d channels (at most %d)\n", in[0].path, channel_count,
                    VBL_MERGE_MAX_CHANNELS);
            code = VBL_EXIT_BAD_INPUT;
        }
    }
    /* every input (the first included), read one at a time into the library's merger
     * (vbl_film_merger: double running sums; vbl/vbl_film.h has the rules) */
    vbl_film_merger* merger = NULL;
    char color_space[1024] = "";
    if (code == VBL_EXIT_OK && vbl_film_merger_create(&merger)) code = vbl_cli_fail(VBL_ERROR_OUT_OF_MEMORY);
    for (int i = 0; i < count && code == VBL_EXIT_OK; ++i) {
        if (i > 0) code = vbl_merge_open(&in[i], &in[0], &first_id);
        if (code != VBL_EXIT_OK) break;
        for (int j = 0; j < i; ++j)
            if (in[i].first_pass <= in[j].first_pass + in[j].passes - 1 &&
                in[j].first_pass <= in[i].first_pass + in[i].passes - 1) {
                fprintf(stderr, "vbl merge: %s (passes %d-%d) overlaps %s (passes %d-%d): pass ranges must be disjoint\n",
                        in[i].path, in[i].first_pass, in[i].first_pass + in[i].passes - 1, in[j].path, in[j].first_pass,
                        in[j].first_pass + in[j].passes - 1);
                code = VBL_EXIT_BAD_INPUT;
            }
        if (code != VBL_EXIT_OK) break;
        /* A part rewritten by a tool that drops oiio:ColorSpace (oiiotool) takes the others' space. */
        const char* space = vbl_exr_image_attribute(in[i].image, "oiio:ColorSpace", NULL);
        if (!color_space[0] && space) snprintf(color_space, sizeof color_space, "%s", space);
        vbl_film* film = NULL;
        vbl_result r = vbl_cli_film_from_exr(in[i].image, in[i].path, in[i].passes, &film);
        if (!r) r = vbl_film_merger_add(merger, film);
        vbl_film_release(film);
        if (r) {
            fprintf(stderr, "vbl merge: %s: %s\n", in[i].path, vbl_last_error_message());
            code = vbl_cli_exit_code(r) == VBL_EXIT_USAGE ? VBL_EXIT_BAD_INPUT : vbl_cli_exit_code(r);
        }
        if (i > 0) {
            vbl_exr_image_release(in[i].image);
            in[i].image = NULL;
        }
    }

    /* pass ranges: sorted, disjoint, and (without --allow-gaps) covering 0..N-1 */
    /* 64-bit sums: two parts of 2147483647 passes overflowed an int ("-2 passes from 2 files") */
    int64_t total = 0, requested = 0, next = 0;
    int gaps = 0, complete = 1, first_pass = 0, last = 0;
    double seconds = 0.0;
    vbl_merge_input* sorted = NULL;
    if (code == VBL_EXIT_OK) {
        sorted = malloc(sizeof *sorted * (size_t)count);
        if (!sorted) code = VBL_EXIT_FAILURE;
    }
    if (code == VBL_EXIT_OK) {
        memcpy(sorted, in, sizeof *sorted * (size_t)count);
        qsort(sorted, (size_t)count, sizeof *sorted, vbl_merge_by_first_pass);
        for (int i = 0; i < count; ++i) {
            const vbl_merge_input* s = &sorted[i];
            const int64_t end = (int64_t)s->first_pass + s->passes - 1;
            if (i > 0 && s->first_pass < next) {
                fprintf(stderr,
                        "vbl merge: %s (passes %d-%lld) overlaps %s (passes %d-%lld): pass ranges must be disjoint\n",
                        s->path, s->first_pass, (long long)end, sorted[i - 1].path, sorted[i - 1].first_pass,
                        (long long)(next - 1));
                code = VBL_EXIT_BAD_INPUT;
                break;
            }
            if (s->first_pass > next) {
                if (!allow_gaps) {
                    fprintf(stderr,
                            "vbl merge: passes %lld-%d are missing (before %s, which starts at pass %d); a single render "
                            "would have them (render them with --pass-range %lld-%d, or merge with --allow-gaps)\n",
                            (long long)next, s->first_pass - 1, s->path, s->first_pass, (long long)next,
                            s->first_pass - 1);
                    code = VBL_EXIT_BAD_INPUT;
                    break;
                }
                gaps = 1;
            }
            next = end + 1;
            total += s->passes;
            requested += s->requested > s->passes ? s->requested : s->passes;
            complete &= s->complete;
            seconds += s->seconds;
        }
        first_pass = sorted[0].first_pass;
        if (code == VBL_EXIT_OK && (next - 1 > INT32_MAX || requested > INT32_MAX)) {
            fprintf(stderr,
                    "vbl merge: the parts end at pass %lld and request %lld passes, beyond the 2147483647 an EXR int "
                    "attribute holds (a part's vbl:passes or vbl:first_pass is wrong)\n",
                    (long long)(next - 1), (long long)requested);
            code = VBL_EXIT_BAD_INPUT;
        }
        last = (int)(next - 1);
    }

    /* the merged film (beauty R,G,B re-summed from the transport layers) as the first input's channels */
    float* planes[VBL_MERGE_MAX_CHANNELS] = {NULL};
    vbl_film* merged = NULL;
    if (code == VBL_EXIT_OK) {
        vbl_result r = vbl_film_merger_finish(merger, &merged);
        if (r) code = vbl_cli_fail(r);
    }
    for (int c = 0; c < channel_count && code == VBL_EXIT_OK; ++c) {
        planes[c] = malloc(sizeof(float) * (n ? n : 1));
        if (!planes[c]) {
            fprintf(stderr, "vbl merge: out of memory\n");
            code = VBL_EXIT_FAILURE;
        } else if (!vbl_cli_film_channel(merged, vbl_exr_image_channel_name(in[0].image, c), planes[c], n)) {
            fprintf(stderr, "vbl merge: internal error: no merged channel '%s'\n",
                    vbl_exr_image_channel_name(in[0].image, c));
            code = VBL_EXIT_FAILURE;
        }
    }
    if (code == VBL_EXIT_OK) {
        const char* status = gaps || !complete ? "partial" : "complete";
        const vbl_merge_summary summary = {(int)total, first_pass, last, (int)requested, status, seconds,
                                           color_space[0] ? color_space : NULL};
        code = vbl_merge_write(out_path, in, count, planes, in[0].image, &summary);
        if (code == VBL_EXIT_OK && !quiet)
            fprintf(stderr, "vbl merge: wrote %s (%lld passes from %d files, passes %d-%d%s)\n", out_path,
                    (long long)total, count, first_pass, last, gaps ? ", with gaps" : "");
    }
    for (int c = 0; c < VBL_MERGE_MAX_CHANNELS; ++c) free(planes[c]);
    vbl_film_release(merged);
    vbl_film_merger_destroy(merger);
    for (int i = 0; i < count; ++i)
        if (in[i].image) vbl_exr_image_release(in[i].image);
    free(sorted);
    free(in);
    return code;
}

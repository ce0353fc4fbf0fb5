/* The benchmarks' shared reference cache and error measures (bench_reference.h). */
#include "bench_reference.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h" /* the camera resolution */

const char* const bench_layer_names[BENCH_LAYERS] = {"",
                                                     "emission",
                                                     "surface_direct",
                                                     "volume_direct",
                                                     "surface_from_surface",
                                                     "surface_from_volume",
                                                     "volume_from_surface",
                                                     "volume_from_volume",
                                                     "medium"};

const char* bench_layer_label(int layer) { return layer == 0 ? "beauty" : bench_layer_names[layer]; }

int bench_film_rgb(const vbl_film* film, int layer, int n, float* out)
{
    int ch = 0, che = 0;
    const int medium = layer == BENCH_LAYER_MEDIUM;
    const float* p = vbl_film_layer(film, medium ? "" : bench_layer_names[layer], &ch);
    const float* e = medium ? vbl_film_layer(film, "emission", &che) : NULL;
    if (!p || ch < 3) {
        memset(out, 0, sizeof(float) * 3 * (size_t)n);
        return 0;
    }
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            out[3 * i + k] = p[(size_t)ch * i + k] - (e && che >= 3 ? e[(size_t)che * i + k] : 0.0f);
    return 1;
}

double bench_rmae(const float* img, const float* ref, int count)
{
    double num = 0.0, den = 0.0;
    for (int i = 0; i < count; ++i) {
        num += fabs((double)img[i] - ref[i]);
        den += fabs((double)ref[i]);
    }
    return den > 0.0 ? num / den : NAN;
}

int bench_in_list(const char* list, const char* name)
{
    size_t len = strlen(name);
    for (const char* s = list; *s;) {
        const char* e = strchr(s, ',');
        size_t l = e ? (size_t)(e - s) : strlen(s);
        if (l == len && !strncmp(s, name, len)) return 1;
        if (!e) break;
        s = e + 1;
    }
    return 0;
}

vbl_scene* bench_load_scene(const char* tool, const char* source_dir, const char* file, const char* vdb, int width,
                            int height)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", source_dir, file);
    const char* overrides[1] = {vdb};
    vbl_scene_load_options lo = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    lo.vdb_overrides = overrides;
    lo.vdb_override_count = vdb ? 1 : 0;
    vbl_scene* scene = NULL;
    if (vbl_scene_load_ex(path, &lo, &scene)) {
        fprintf(stderr, "%s: %s\n", tool, vbl_last_error_message());
        exit(1);
    }
    /* same field of view at the bench resolution (the scene is not shared yet) */
    scene->camera.width = width;
    scene->camera.height = height;
    return scene;
}

/* 1 if txt's key matches (exactly, or loosely with any_cached) and raw holds both halves. */
static int load_cached(const char* raw, const char* txt, const bench_reference_request* q, bench_reference* r)
{
    FILE* f = fopen(txt, "r");
    if (!f) return 0;
    char have[2048] = {0};
    size_t got = fread(have, 1, sizeof have - 1, f);
    fclose(f);
    have[got] = '\0';
    char* nl = strchr(have, '\n');
    if (!nl) return 0;
    *nl = '\0';
    if (q->any_cached) {
        char want_scene[512], want_res[128];
        snprintf(want_scene, sizeof want_scene, "scene=%s vdb=", q->file);
        snprintf(want_res, sizeof want_res, " res=%dx%d method=pt ", q->width, q->height);
        if (strncmp(have, want_scene, strlen(want_scene)) || !strstr(have, want_res) || !strstr(have, "layers=9 rgb"))
            return 0;
    } else if (strcmp(have, r->key)) {
        return 0;
    }
    /* second line: the present flags */
    for (int l = 0; l < BENCH_LAYERS; ++l) {
        if (nl[1 + l] != '0' && nl[1 + l] != '1') return 0;
        r->present[l] = nl[1 + l] == '1';
    }
    f = fopen(raw, "rb");
    if (!f) return 0;
    size_t want_count = (size_t)2 * BENCH_LAYERS * 3 * r->n;
    size_t count = fread(r->halves, sizeof(float), want_count, f);
    fclose(f);
    if (count != want_count) return 0;
    snprintf(r->key, sizeof r->key, "%s", have);
    return 1;
}

static void render_halves(const vbl_scene* scene, const bench_reference_request* q, bench_reference* r)
{
    for (int h = 0; h < 2; ++h) {
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        vbl_scene_render_options(scene, &o);
        o.method = VBL_RENDER_PT;
        o.spp = 4;
        o.passes = 1000000000; /* the options table's maximum; the time limit ends it */
        o.time_limit = 0.5 * q->seconds;
        o.seed = 4242u + 7919u * (uint64_t)h;
        o.threads = q->threads;
        vbl_film* film = NULL;
        if (vbl_render(scene, &o, &film)) {
            fprintf(stderr, "%s: %s\n", q->tool, vbl_last_error_message());
            exit(1);
        }
        vbl_film_stats st;
        memset(&st, 0, sizeof st);
        st.size = sizeof st;
        vbl_film_get_stats(film, &st);
        printf("# reference half %d: pt %d passes x %d spp in %.1f s\n", h, st.passes, st.spp, st.render_seconds);
        for (int l = 0; l < BENCH_LAYERS; ++l)
            r->present[l] = bench_film_rgb(film, l, r->n, r->halves + ((size_t)h * BENCH_LAYERS + l) * 3 * r->n);
        vbl_film_release(film);
    }
}

static void save_cached(const char* raw, const char* txt, const bench_reference_request* q, const bench_reference* r)
{
    size_t count = (size_t)2 * BENCH_LAYERS * 3 * r->n;
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp", raw);
    FILE* f = fopen(tmp, "wb");
    if (!f || fwrite(r->halves, sizeof(float), count, f) != count || fclose(f)) {
        fprintf(stderr, "%s: cannot write %s (reference not cached)\n", q->tool, tmp);
        return;
    }
    rename(tmp, raw);
    f = fopen(txt, "w");
    if (!f) return;
    fprintf(f, "%s\n", r->key);
    for (int l = 0; l < BENCH_LAYERS; ++l) fputc(r->present[l] ? '1' : '0', f);
    fputc('\n', f);
    fclose(f);
}

void bench_reference_make(const vbl_scene* scene, const bench_reference_request* q, bench_reference* r)
{
    memset(r, 0, sizeof *r);
    r->width = q->width;
    r->height = q->height;
    r->n = q->width * q->height;
    r->seconds = q->seconds;
    size_t per = (size_t)BENCH_LAYERS * 3 * r->n;
    r->halves = calloc(2 * per, sizeof(float));
    r->ref = calloc(per, sizeof(float));
    if (!r->halves || !r->ref) exit(1);
    char raw[1024], txt[1024];
    snprintf(raw, sizeof raw, "%s/bench_curves_ref_%s_%dx%d.raw", q->cache_dir, q->name, q->width, q->height);
    snprintf(txt, sizeof txt, "%s/bench_curves_ref_%s_%dx%d.txt", q->cache_dir, q->name, q->width, q->height);
    snprintf(r->key, sizeof r->key, "scene=%s vdb=%s res=%dx%d method=pt spp=4 seconds=%g halves=2 layers=%d rgb",
             q->file, q->vdb, q->width, q->height, q->seconds, BENCH_LAYERS);
    if (load_cached(raw, txt, q, r)) {
        printf("# reference %s: cached %s (%s)\n", q->name, raw, r->key);
    } else {
        printf("# reference %s: rendering %s\n", q->name, r->key);
        fflush(stdout);
        render_halves(scene, q, r);
        save_cached(raw, txt, q, r);
    }
    for (size_t i = 0; i < per; ++i) r->ref[i] = 0.5f * (r->halves[i] + r->halves[per + i]);
    /* E|A - B| = 2 E|mean - truth| for independent halves with equal (normal) noise */
    for (int l = 0; l < BENCH_LAYERS; ++l) {
        const float* a0 = r->halves + (size_t)l * 3 * r->n;
        const float* b0 = r->halves + per + (size_t)l * 3 * r->n;
        double num = 0.0, den = 0.0;
        for (int i = 0; i < 3 * r->n; ++i) {
            num += fabs((double)a0[i] - b0[i]);
            den += fabs(0.5 * ((double)a0[i] + b0[i]));
        }
        r->floor_rmae[l] = r->present[l] && den > 0.0 ? 0.5 * num / den : NAN;
    }
}

#define _POSIX_C_SOURCE 200809L
#include "render_test_util.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "temp_scene.h"
#include "volume_test_grid.h"

void rt_make_temp_dir(char* out)
{
    const char* base = getenv("TMPDIR");
    snprintf(out, 256, "%s/vbl_render_test_XXXXXX", base && base[0] ? base : "/tmp");
    if (!mkdtemp(out)) {
        fprintf(stderr, "mkdtemp failed\n");
        abort();
    }
}

void rt_write_file(const char* dir, const char* name, const char* text, char* out)
{
    snprintf(out, 512, "%s/%s", dir, name);
    FILE* f = fopen(out, "wb");
    if (!f) abort();
    fputs(text, f);
    fclose(f);
}

int rt_merge_scene_write(const char* prefix, char* path, size_t path_size)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    if (!fixtures) return -1;
    return vbl_test_temp_scene_write(prefix, path, path_size,
            "{\"camera\": {\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40,"
            " \"resolution\": [12, 9]},\n"
            " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [2.0, 1.8, 1.5]},"
            " {\"type\": \"environment\", \"radiance\": [0.10, 0.12, 0.20]}],\n"
            " \"media\": [{\"vdb\": \"%s/box.vdb\", \"density_scale\": 3.0, \"albedo\": [0.9, 0.8, 0.7],"
            " \"phase\": {\"type\": \"hg\", \"g\": 0.3}}],\n"
            " \"render\": {\"passes\": 4, \"spp\": 2, \"seed\": 5, \"light_paths\": 40}}\n",
            fixtures);
}

vbl_scene* rt_ramp_box_load(double density_scale, double albedo, int res, const char* medium_extra)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    char text[2048], path[512];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0.75, -6, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 20, "
             "\"resolution\": [%d, %d]}, \"lights\": [{\"type\": \"distant\", \"direction\": [-0.6, 0.3, -1], "
             "\"irradiance\": 2}], \"media\": [{\"vdb\": \"%s/albedo_ramp.vdb\", \"density_scale\": %.17g, "
             "\"albedo\": %.17g%s}]}",
             res, res, fixtures ? fixtures : "tests/fixtures", density_scale, albedo, medium_extra);
    rt_write_file(rt_temp_dir, "scene.json", text, path);
    vbl_scene* scene = NULL;
    if (vbl_scene_load(path, &scene) != VBL_SUCCESS) {
        printf("load failed: %s\n", vbl_last_error_message());
        return NULL;
    }
    return scene;
}

int rt_layer_mean(const vbl_film* film, const char* layer, double* mean)
{
    int c = 0, w = vbl_film_width(film), h = vbl_film_height(film);
    const float* p = vbl_film_layer(film, layer, &c);
    if (!p) return -1;
    double m = 0.0;
    for (int i = 0; i < w * h; ++i)
        for (int ch = 0; ch < 3; ++ch) {
            if (!isfinite(p[i * c + ch])) return -1;
            m += p[i * c + ch];
        }
    *mean = m / (3.0 * w * h);
    return 0;
}

int rt_layer_replicas(const vbl_scene* scene, const vbl_render_options* base, const char* layer, int n,
                      uint64_t seed0, double* mean, double* se)
{
    double s = 0.0, s2 = 0.0;
    for (int k = 0; k < n; ++k) {
        vbl_render_options o = *base;
        o.seed = seed0 + (uint64_t)k;
        vbl_film* film = NULL;
        if (vbl_render(scene, &o, &film) != VBL_SUCCESS) {
            printf("render failed: %s\n", vbl_last_error_message());
            return -1;
        }
        double m = 0.0;
        const int bad = rt_layer_mean(film, layer, &m);
        vbl_film_release(film);
        if (bad) return -1;
        s += m;
        s2 += m * m;
    }
    *mean = s / n;
    *se = sqrt(fmax(0.0, (s2 - n * *mean * *mean) / (n - 1.0)) / n);
    return 0;
}

vbl_scene* rt_lit_box;
static char rt_lit_box_path[512];

int rt_lit_box_setup(int w, int h, double density_scale)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    if (vbl_test_temp_scene_write(
            "vbl_lit_box", rt_lit_box_path, sizeof rt_lit_box_path,
            "{\"camera\": {\"position\": [0.75, -3, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40, "
            "\"resolution\": [%d, %d]}, "
            "\"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": [1, 1, 1]}], "
            "\"media\": [{\"vdb\": \"%s/box.vdb\", \"albedo\": [0.8, 0.8, 0.8], \"density_scale\": %.17g}]}",
            w, h, fixtures ? fixtures : "tests/fixtures", density_scale) != 0)
        return -1;
    return vbl_scene_load(rt_lit_box_path, &rt_lit_box) == VBL_SUCCESS ? 0 : -1;
}

int rt_lit_box_teardown(void** state)
{
    (void)state;
    vbl_scene_release(rt_lit_box);
    rt_lit_box = NULL;
    vbl_test_temp_scene_remove(rt_lit_box_path);
    return 0;
}

void rt_remove_dir(const char* dir)
{
    DIR* d = opendir(dir);
    if (!d) return;
    struct dirent* e;
    char path[1024];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        remove(path);
    }
    closedir(d);
    rmdir(dir);
}

char rt_temp_dir[256];

int rt_temp_dir_setup(void** state)
{
    (void)state;
    rt_make_temp_dir(rt_temp_dir);
    return 0;
}

int rt_temp_dir_teardown(void** state)
{
    (void)state;
    rt_remove_dir(rt_temp_dir);
    return 0;
}

static double rt_one(int i, int j, int k, void* user)
{
    (void)i, (void)j, (void)k, (void)user;
    return 1.0;
}

vbl_volume* rt_make_box(int n, double h, vbl_vec3 origin)
{
    int bmin[3] = {0, 0, 0}, bmax[3] = {n - 1, n - 1, n - 1};
    double m[3][4];
    vt_uniform_map(m, h, origin.x, origin.y, origin.z);
    return vt_make(bmin, bmax, rt_one, NULL, m);
}

static double rt_profile(int n, double u)
{
    if (u <= -1.0 || u >= n) return 0.0;
    if (u < 0.0) return u + 1.0;
    if (u > n - 1) return n - u;
    return 1.0;
}

double rt_box_density(int n, double h, vbl_vec3 origin, vbl_vec3 p)
{
    return rt_profile(n, (p.x - origin.x) / h) * rt_profile(n, (p.y - origin.y) / h) *
           rt_profile(n, (p.z - origin.z) / h);
}

vbl_camera rt_camera(vbl_vec3 position, vbl_vec3 target, double fov_deg, int w, int h)
{
    vbl_camera cam;
    if (vbl_camera_make(position, target, vbl_v3(0, 0, 1), fov_deg, w, h, &cam)) abort();
    return cam;
}

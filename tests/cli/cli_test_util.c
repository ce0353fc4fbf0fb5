#define _POSIX_C_SOURCE 200809L
#include "cli_test_util.h"

#include <dirent.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

const char* ct_vbl(void)
{
    static char path[1024];
    const char* bin = getenv("VBL_BINARY_DIR");
    snprintf(path, sizeof path, "%s/bin/vbl", bin ? bin : ".");
    return path;
}

const char* ct_fixture(const char* name)
{
    static char path[1024];
    const char* dir = getenv("VBL_FIXTURE_DIR");
    snprintf(path, sizeof path, "%s/%s", dir ? dir : ".", name);
    return path;
}

char* ct_make_dir(void)
{
    const char* base = getenv("TMPDIR");
    char* dir = malloc(1024);
    if (!dir) abort();
    snprintf(dir, 1024, "%s/vbl-cli-XXXXXX", base && base[0] ? base : "/tmp");
    if (!mkdtemp(dir)) {
        fprintf(stderr, "mkdtemp failed\n");
        abort();
    }
    return dir;
}

void ct_remove_dir(const char* dir)
{
    DIR* d = opendir(dir);
    if (!d) return;
    struct dirent* e;
    char path[2048];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        remove(path);
    }
    closedir(d);
    rmdir(dir);
}

const char* ct_path(const char* dir, const char* name)
{
    static char slots[8][2048];
    static int next = 0;
    char* p = slots[next++ & 7];
    snprintf(p, 2048, "%s/%s", dir, name);
    return p;
}

void ct_write_file(const char* path, const char* text)
{
    FILE* f = fopen(path, "wb");
    if (!f) abort();
    fputs(text, f);
    fclose(f);
}

int ct_count_entries(const char* dir, char* names, int size)
{
    DIR* d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    size_t used = 0;
    if (names && size > 0) names[0] = 0;
    struct dirent* e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        if (names && used + 2 < (size_t)size)
            used += (size_t)snprintf(names + used, (size_t)size - used, "%s%s", n ? "," : "", e->d_name);
        ++n;
    }
    closedir(d);
    return n;
}

int ct_render(const char* args, char** output)
{
    size_t len = strlen(args) + 16;
    char* full = malloc(len);
    if (!full) abort();
    snprintf(full, len, "render %s", args);
    int code = ct_vbl_run(full, output, 1);
    free(full);
    return code;
}

int ct_vbl_run(const char* args, char** output, int with_stderr)
{
    size_t len = strlen(args) + 2048;
    char* cmd = malloc(len);
    if (!cmd) abort();
    snprintf(cmd, len, "'%s' %s %s", ct_vbl(), args, with_stderr ? "2>&1" : "2>/dev/null");
    FILE* p = popen(cmd, "r");
    free(cmd);
    if (!p) return -1;
    size_t cap = 4096, n = 0;
    char* text = malloc(cap);
    size_t got;
    while (text && (got = fread(text + n, 1, cap - n - 1, p)) > 0) {
        n += got;
        if (cap - n < 1024) text = realloc(text, cap *= 2);
    }
    if (text) text[n] = 0;
    int status = pclose(p);
    if (output) *output = text;
    else free(text);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void ct_write_scene(const char* path, int width, int height, const char* extra_top_level)
{
    char text[4096];
    snprintf(text, sizeof text,
             "{\n%s"
             "  \"camera\": {\"position\": [0.75, -3.0, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40,\n"
             "             \"resolution\": [%d, %d]},\n"
             "  \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, 0.5, -0.8], \"irradiance\": [2.0, 1.8, 1.5]},\n"
             "             {\"type\": \"environment\", \"radiance\": [0.10, 0.12, 0.20]}],\n"
             "  \"media\": [{\"vdb\": \"%s\", \"density_scale\": 3.0, \"albedo\": [0.9, 0.8, 0.7],\n"
             "              \"phase\": {\"type\": \"hg\", \"g\": 0.3}}],\n"
             "  \"render\": {\"method\": \"pt\", \"passes\": 2, \"spp\": 2, \"seed\": 3, \"max_bounces\": 4}\n"
             "}\n",
             extra_top_level ? extra_top_level : "", width, height, ct_fixture("box.vdb"));
    ct_write_file(path, text);
}

uint64_t ct_fnv1a64_file(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    uint64_t h = 0xcbf29ce484222325ull;
    int c;
    while ((c = fgetc(f)) != EOF) h = (h ^ (uint64_t)(unsigned char)c) * 0x100000001b3ull;
    fclose(f);
    return h;
}

int ct_png_info(const char* path, int* width, int* height, int* bit_depth, int* color_type)
{
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    unsigned char sig[8];
    int ok = fread(sig, 1, 8, f) == 8 && !png_sig_cmp(sig, 0, 8);
    png_structp png = ok ? png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL) : NULL;
    png_infop info = png ? png_create_info_struct(png) : NULL;
    ok = ok && png && info;
    if (ok && setjmp(png_jmpbuf(png))) ok = 0;
    else if (ok) {
        png_init_io(png, f);
        png_set_sig_bytes(png, 8);
        png_read_info(png, info);
        *width = (int)png_get_image_width(png, info);
        *height = (int)png_get_image_height(png, info);
        *bit_depth = png_get_bit_depth(png, info);
        *color_type = png_get_color_type(png, info);
    }
    if (png) png_destroy_read_struct(&png, info ? &info : NULL, NULL);
    fclose(f);
    return ok;
}

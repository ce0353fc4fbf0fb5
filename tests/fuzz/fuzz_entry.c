/* Fuzz entry points (fuzz_entry.h). */
#define _POSIX_C_SOURCE 200809L
#include "fuzz_entry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "geometry/mesh_load.h"
#include "vbl/vbl.h"
#include "vbl_exr.h"

static char g_dir[4096];

static void vbl_fuzz_remove_dir(void)
{
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
    if (system(cmd) != 0) fprintf(stderr, "fuzz: cannot remove %s\n", g_dir);
}

/* Writes the input to <private dir>/input.<ext>; returns the path (static) or NULL. */
static const char* vbl_fuzz_file(const uint8_t* data, size_t size, const char* ext)
{
    static char path[4200];
    if (!g_dir[0]) {
        const char* tmp = getenv("TMPDIR");
        snprintf(g_dir, sizeof g_dir, "%s/vbl_fuzz_XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(g_dir)) {
            g_dir[0] = '\0';
            return NULL;
        }
        atexit(vbl_fuzz_remove_dir);
    }
    snprintf(path, sizeof path, "%s/input.%s", g_dir, ext);
    FILE* f = fopen(path, "wb");
    if (!f) return NULL;
    size_t written = size ? fwrite(data, 1, size, f) : 0;
    fclose(f);
    return written == size ? path : NULL;
}

void vbl_fuzz_volume(const uint8_t* data, size_t size)
{
    const int nano = size >= 7 && !memcmp(data, "NanoVDB", 7);
    const char* path = vbl_fuzz_file(data, size, nano ? "nvdb" : "vdb");
    if (!path) return;
    vbl_volume* volume = NULL;
    if (vbl_volume_load(path, NULL, &volume) == VBL_SUCCESS) vbl_volume_release(volume);
    vbl_grid_description* grids = NULL;
    size_t count = 0;
    if (vbl_file_list_grids(path, &grids, &count) == VBL_SUCCESS) vbl_grid_descriptions_free(grids);
}

void vbl_fuzz_scene(const uint8_t* data, size_t size)
{
    const char* path = vbl_fuzz_file(data, size, "json");
    if (!path) return;
    vbl_scene* scene = NULL;
    if (vbl_scene_load(path, &scene) == VBL_SUCCESS) vbl_scene_release(scene);
}

void vbl_fuzz_exr(const uint8_t* data, size_t size)
{
    const char* path = vbl_fuzz_file(data, size, "exr");
    if (!path) return;
    vbl_exr_image* image = NULL;
    if (vbl_exr_read(path, &image) == VBL_SUCCESS) vbl_exr_image_release(image);
}

void vbl_fuzz_mesh(const uint8_t* data, size_t size)
{
    const int ply = size >= 3 && !memcmp(data, "ply", 3);
    const char* path = vbl_fuzz_file(data, size, ply ? "ply" : "obj");
    if (!path) return;
    vbl_mesh_data mesh;
    if (vbl_mesh_load(path, &mesh, NULL) == VBL_SUCCESS) vbl_mesh_data_free(&mesh);
}

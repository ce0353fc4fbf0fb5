#define _POSIX_C_SOURCE 200809L
#include "temp_scene.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int vbl_test_temp_scene_write(const char* prefix, char* path, size_t path_size, const char* format, ...)
{
    char dir[512];
    if (snprintf(dir, sizeof dir, "/tmp/%s_XXXXXX", prefix) >= (int)sizeof dir || !mkdtemp(dir)) return -1;
    if (snprintf(path, path_size, "%s/scene.json", dir) >= (int)path_size) return -1;
    FILE* f = fopen(path, "w");
    if (!f) return -1;
    va_list args;
    va_start(args, format);
    int written = vfprintf(f, format, args);
    va_end(args);
    return (fclose(f) == 0 && written >= 0) ? 0 : -1;
}

void vbl_test_temp_scene_remove(const char* path)
{
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", path);
    unlink(path);
    char* slash = strrchr(dir, '/');
    if (slash) *slash = 0, rmdir(dir);
}

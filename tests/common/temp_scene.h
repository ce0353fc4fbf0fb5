/* A scene file in a fresh temporary folder, the fixture most render tests start from. */
#ifndef VBL_TEST_TEMP_SCENE_H
#define VBL_TEST_TEMP_SCENE_H

#include <stddef.h>

/* Creates /tmp/<prefix>_XXXXXX and writes the printf-formatted scene text to scene.json in it;
 * the file's path goes to path. Returns 0, or -1 when the folder or the file cannot be made. */
int vbl_test_temp_scene_write(const char* prefix, char* path, size_t path_size, const char* format, ...)
    __attribute__((format(printf, 4, 5)));

/* Removes the scene file and its folder (the folder only if it is then empty). */
void vbl_test_temp_scene_remove(const char* path);

#endif

/* Internals of the EXR plug-in: atomic output files and a write-failure hook for tests. */
#ifndef VBL_EXR_INTERNAL_H
#define VBL_EXR_INTERNAL_H

#include <stdint.h>

#include "vbl_exr.h"

/* A file being written: opened under a unique temporary name beside `path`. */
typedef struct vbl_exr_output_file {
    int fd;
    char* final_path;
    char* temp_path;
    int64_t bytes_written;
    int failed_errno;      /* first write error (errno), 0 if none */
} vbl_exr_output_file;

#ifdef __cplusplus
extern "C" {
#endif
/* Creates "<dir>/.<base>.tmp-XXXXXX". Reports the error (naming `path`) on failure. */
vbl_result vbl_exr_output_open(vbl_exr_output_file* file, const char* path);
/* pwrite()s everything or records the failure; returns bytes written or -1. */
int64_t vbl_exr_output_pwrite(vbl_exr_output_file* file, const void* data, uint64_t size, uint64_t offset);
/* fsync + close + rename over final_path; on failure removes the temporary file. */
vbl_result vbl_exr_output_commit(vbl_exr_output_file* file);
/* Closes and removes the temporary file (no error reported). */
void vbl_exr_output_abort(vbl_exr_output_file* file);

/* Test hook: the next writes fail with ENOSPC once `limit` bytes have been written to a file
 * (-1: off, the default). Shared by all output files of the process; not thread safe. */
void vbl_exr_test_set_write_limit(int64_t limit);
#ifdef __cplusplus
}
#endif


/* OpenEXRCore 3.1 has no DWAA/DWAB codec; those files go through the C++ library (exr_imf.cc). */
typedef struct vbl_exr_plane {
    const char* name;
    int half;              /* data: uint16 half bits if 1, float if 0 */
    const void* data;      /* width*height values, row 0 = top */
} vbl_exr_plane;

#ifdef __cplusplus
extern "C" {
#endif
/* Writes the whole file into `file` (already open). Reports errors naming `path`. */
vbl_result vbl_exr_write_imf(vbl_exr_output_file* file, const char* path, int width, int height,
                             const vbl_exr_plane* planes, int plane_count, const vbl_exr_write_options* options,
                             int tile_size);
/* Decodes the named channels of the first part into float planes of `width` floats per row whose
 * origin is the data window's min corner. Returns 0, or -1 with `message` filled. */
int vbl_exr_read_imf(const char* path, int plane_count, const char* const* names, float* const* planes, int width,
                     char* message, size_t message_size);
#ifdef __cplusplus
}
#endif

#endif

/* Atomic output: write to a unique temporary file beside the target, fsync, rename. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "exr_internal.h"

static int64_t vbl_exr_write_limit = -1;

void vbl_exr_test_set_write_limit(int64_t limit) { vbl_exr_write_limit = limit; }

static char* vbl_exr_strdup(const char* s)
{
    size_t n = strlen(s) + 1;
    char* copy = malloc(n);
    if (copy) memcpy(copy, s, n);
    return copy;
}

vbl_result vbl_exr_output_open(vbl_exr_output_file* file, const char* path)
{
    memset(file, 0, sizeof *file);
    file->fd = -1;
    if (!path || !path[0]) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "EXR output path is empty");
    const char* slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path) + 1 : 0;
    const char* base = slash ? slash + 1 : path;
    if (!base[0]) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "%s: output path names a directory", path);
    size_t n = dir_len + 1 + strlen(base) + sizeof ".tmp-XXXXXX";
    file->temp_path = malloc(n);
    file->final_path = vbl_exr_strdup(path);
    if (!file->temp_path || !file->final_path) {
        free(file->temp_path);
        free(file->final_path);
        file->temp_path = file->final_path = NULL;
        return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    snprintf(file->temp_path, n, "%.*s.%s.tmp-XXXXXX", (int)dir_len, path, base);
    file->fd = mkstemp(file->temp_path);
    if (file->fd < 0) {
        int e = errno;
        free(file->temp_path);
        free(file->final_path);
        file->temp_path = file->final_path = NULL;
        return vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot create a file in its directory: %s", path, strerror(e));
    }
    (void)fchmod(file->fd, 0644);
    return VBL_SUCCESS;
}

int64_t vbl_exr_output_pwrite(vbl_exr_output_file* file, const void* data, uint64_t size, uint64_t offset)
{
    const unsigned char* p = data;
    uint64_t done = 0;
    while (done < size) {
        size_t chunk = (size_t)(size - done);
        if (vbl_exr_write_limit >= 0) {
            int64_t room = vbl_exr_write_limit - (int64_t)(offset + done);
            if (room <= 0) {
                file->failed_errno = ENOSPC;
                return -1;
            }
            if ((uint64_t)room < chunk) chunk = (size_t)room;
        }
        ssize_t w = pwrite(file->fd, p + done, chunk, (off_t)(offset + done));
        if (w < 0) {
            if (errno == EINTR) continue;
            if (!file->failed_errno) file->failed_errno = errno;
            return -1;
        }
        if (w == 0) {
            if (!file->failed_errno) file->failed_errno = ENOSPC;
            return -1;
        }
        done += (uint64_t)w;
    }
    file->bytes_written += (int64_t)done;
    return (int64_t)done;
}

static void vbl_exr_output_free(vbl_exr_output_file* file)
{
    free(file->temp_path);
    free(file->final_path);
    file->temp_path = file->final_path = NULL;
    file->fd = -1;
}

void vbl_exr_output_abort(vbl_exr_output_file* file)
{
    if (file->fd >= 0) close(file->fd);
    if (file->temp_path) unlink(file->temp_path);
    vbl_exr_output_free(file);
}

vbl_result vbl_exr_output_commit(vbl_exr_output_file* file)
{
    const char* step = NULL;
    int e = 0;
    if (fsync(file->fd) != 0) step = "flushing", e = errno;
    if (close(file->fd) != 0 && !step) step = "closing", e = errno;
    file->fd = -1;
    if (!step && rename(file->temp_path, file->final_path) != 0) step = "renaming the temporary file", e = errno;
    if (step) {
        vbl_result r = vbl_report_error(VBL_ERROR_FILE_IO, "%s: %s failed: %s", file->final_path, step, strerror(e));
        unlink(file->temp_path);
        vbl_exr_output_free(file);
        return r;
    }
    vbl_exr_output_free(file);
    return VBL_SUCCESS;
}

/* Loads one volume with vbl_volume_load and prints its NanoVDB size and the process's peak RSS
 * (bench_load_memory.sh runs it on the big generated grids; not a test). */
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

#include "vbl/vbl.h"

int main(int argc, char** argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: bench_load_volume FILE.vdb|FILE.nvdb\n");
        return 2;
    }
    vbl_volume* v = NULL;
    if (vbl_volume_load(argv[1], NULL, &v) != VBL_SUCCESS) {
        fprintf(stderr, "%s\n", vbl_last_error_message());
        return 3;
    }
    vbl_volume_info info;
    memset(&info, 0, sizeof info);
    info.size = sizeof info;
    vbl_volume_get_info(v, &info);
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    const double rss = (double)ru.ru_maxrss * 1024.0; /* KiB on Linux */
    printf("%s: %llu active voxels, NanoVDB %.1f MB, majorant %.1f MB, peak RSS %.1f MB (%.2fx the NanoVDB size)\n", argv[1],
           (unsigned long long)info.active_voxels, info.nanovdb_bytes / 1e6, info.majorant_bytes / 1e6, rss / 1e6,
           rss / (double)info.nanovdb_bytes);
    vbl_volume_release(v);
    return 0;
}

/* How long this process has run: `--time-limit` counts from the exec, so that the dynamic loading
 * of the libraries before main (about 0.1 s idle, over 1 s on a loaded machine) is inside the
 * limit too (bench/results/time_limit_issue13.txt). */
#define _GNU_SOURCE
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "render_cli.h"

double vbl_process_seconds(void)
{
    /* /proc/self/stat field 22: the start time in clock ticks since boot (proc(5)); the command
     * name (field 2) may hold spaces and parentheses, so count from its last ')' */
    FILE* f = fopen("/proc/self/stat", "r");
    if (!f) return 0.0;
    char line[1024];
    size_t n = fread(line, 1, sizeof line - 1, f);
    fclose(f);
    line[n] = 0;
    char* p = strrchr(line, ')');
    if (!p) return 0.0;
    unsigned long long start_ticks = 0;
    int field = 2;
    for (char* tok = strtok(p + 1, " "); tok; tok = strtok(NULL, " "))
        if (++field == 22) {
            if (sscanf(tok, "%llu", &start_ticks) != 1) return 0.0;
            break;
        }
    long hz = sysconf(_SC_CLK_TCK);
    struct timespec now;
    if (field != 22 || hz <= 0 || clock_gettime(CLOCK_BOOTTIME, &now)) return 0.0;
    double elapsed = (double)now.tv_sec + 1e-9 * (double)now.tv_nsec - (double)start_ticks / (double)hz;
    /* a clock that disagrees (a container's own boot time, say): count from main's first call */
    return elapsed >= 0.0 && elapsed < 600.0 ? elapsed : 0.0;
}

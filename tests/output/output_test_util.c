#define _POSIX_C_SOURCE 200809L

#include "output_test_util.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

char* out_make_temp_dir(void)
{
    static char slots[8][64];
    static int next;
    char* dir = slots[next++ % 8];
    const char* base = getenv("TMPDIR");
    snprintf(dir, 64, "%s/vbl-output-XXXXXX", base && base[0] && strlen(base) < 40 ? base : "/tmp");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        abort();
    }
    return dir;
}

void out_remove_dir(const char* dir)
{
    DIR* d = opendir(dir);
    if (d) {
        struct dirent* e;
        while ((e = readdir(d)))
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) unlink(out_path(dir, e->d_name));
        closedir(d);
    }
    rmdir(dir);
}

int out_count_entries(const char* dir, char* first, int first_size)
{
    int n = 0;
    DIR* d = opendir(dir);
    if (!d) return -1;
    struct dirent* e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            if (n == 0 && first) snprintf(first, (size_t)first_size, "%s", e->d_name);
            ++n;
        }
    closedir(d);
    return n;
}

const char* out_path(const char* dir, const char* name)
{
    static char slots[8][1024];
    static int next;
    char* p = slots[next++ % 8];
    snprintf(p, 1024, "%s/%s", dir, name);
    return p;
}

int out_run(const char* command, char** output)
{
    char full[9000];
    snprintf(full, sizeof full, "%s 2>&1", command);
    FILE* pipe = popen(full, "r");
    if (!pipe) return -1;
    size_t cap = 4096, len = 0;
    char* buf = malloc(cap);
    size_t n;
    while (buf && (n = fread(buf + len, 1, cap - len - 1, pipe)) > 0) {
        len += n;
        if (cap - len < 2) {
            char* grown = realloc(buf, cap * 2);
            if (!grown) break;
            buf = grown;
            cap *= 2;
        }
    }
    if (buf) buf[len] = '\0';
    int status = pclose(pipe);
    if (output) *output = buf;
    else free(buf);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

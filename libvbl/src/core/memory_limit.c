/* The process-wide memory limit: default from VBL_MEMORY_LIMIT or 3/4 of the physical memory,
 * overridden by vbl_set_memory_limit (the CLI's --memory-limit). */
#define _POSIX_C_SOURCE 200809L
#include "core/memory_limit.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "core/error.h"

#define VBL_MEMORY_LIMIT_FLOOR ((uint64_t)256 << 20) /* default never under 256 MiB */
#define VBL_MEMORY_LIMIT_MIN ((uint64_t)64 << 10)    /* smallest limit one may set */

static uint64_t g_limit; /* 0: not set, use the default (read with __atomic) */
static uint64_t g_default;

static uint64_t physical_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return (uint64_t)8 << 30; /* unknown: assume 8 GiB */
    return (uint64_t)pages * (uint64_t)page;
}

VBL_API vbl_result vbl_parse_memory_size(const char* text, uint64_t* out_bytes)
{
    if (!text || !out_bytes) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_parse_memory_size: NULL argument");
    char quoted[64];
    size_t n = 0;
    for (const char* c = text; *c && n + 5 < sizeof quoted; ++c) /* quote without raw bytes */
        n += (size_t)snprintf(quoted + n, sizeof quoted - n, isprint((unsigned char)*c) ? "%c" : "\\x%02x", (unsigned char)*c);
    errno = 0;
    char* end = NULL;
    const double value = strtod(text, &end);
    if (end == text || errno || !isfinite(value) || value <= 0.0 || isspace((unsigned char)text[0]))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "memory size '%s' is not a positive number with an optional K/M/G/T or %% suffix", quoted);
    double scale = 1.0;
    if (!strcmp(end, "%")) {
        if (value > 100.0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "memory size '%s' is over 100%%", quoted);
        scale = (double)physical_memory() / 100.0;
    } else if (*end) {
        const char* units = "KMGT";
        const char* u = strchr(units, toupper((unsigned char)*end));
        if (!u) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "memory size '%s' has an unknown unit (use K, M, G or T)", quoted);
        for (const char* k = units; k <= u; ++k) scale *= 1024.0;
        const char* rest = end + 1;
        if (strcmp(rest, "") && strcasecmp(rest, "B") && strcasecmp(rest, "iB"))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "memory size '%s' has an unknown unit (use K, M, G or T)", quoted);
    }
    const double bytes = value * scale;
    if (bytes >= 18446744073709551615.0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "memory size '%s' is too large", quoted);
    *out_bytes = (uint64_t)bytes;
    return VBL_SUCCESS;
}

static uint64_t default_limit(void)
{
    uint64_t d = __atomic_load_n(&g_default, __ATOMIC_RELAXED);
    if (d) return d;
    uint64_t bytes = 0;
    const char* env = getenv("VBL_MEMORY_LIMIT");
    /* A malformed VBL_MEMORY_LIMIT is ignored here (the library never prints); the CLI reports it. */
    if (!(env && env[0] && vbl_parse_memory_size(env, &bytes) == VBL_SUCCESS && bytes >= VBL_MEMORY_LIMIT_MIN)) {
        vbl_clear_error();
        bytes = physical_memory() / 4 * 3;
        if (bytes < VBL_MEMORY_LIMIT_FLOOR) bytes = VBL_MEMORY_LIMIT_FLOOR;
    }
    __atomic_store_n(&g_default, bytes, __ATOMIC_RELAXED);
    return bytes;
}

VBL_API uint64_t vbl_memory_limit(void)
{
    const uint64_t set = __atomic_load_n(&g_limit, __ATOMIC_RELAXED);
    return set ? set : default_limit();
}

VBL_API vbl_result vbl_set_memory_limit(uint64_t bytes)
{
    if (bytes && bytes < VBL_MEMORY_LIMIT_MIN)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "memory limit %llu bytes is under the 64 KiB minimum", (unsigned long long)bytes);
    __atomic_store_n(&g_limit, bytes, __ATOMIC_RELAXED);
    return VBL_SUCCESS;
}

void vbl_memory_limit_message(char* out, size_t size, uint64_t bytes, const char* what)
{
    snprintf(out, size, "%s needs %.1f MiB, more than the memory limit of %.1f MiB (--memory-limit / VBL_MEMORY_LIMIT)",
             what ? what : "input", (double)bytes / 1048576.0, (double)vbl_memory_limit() / 1048576.0);
}

vbl_result vbl_memory_check(uint64_t bytes, const char* path, const char* what)
{
    if (bytes <= vbl_memory_limit()) return VBL_SUCCESS;
    char text[512];
    vbl_memory_limit_message(text, sizeof text, bytes, what);
    return path ? vbl_error(VBL_ERROR_UNSUPPORTED, "%s: %s", path, text) : vbl_error(VBL_ERROR_UNSUPPORTED, "%s", text);
}

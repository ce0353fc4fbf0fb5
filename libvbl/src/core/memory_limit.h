/* The process-wide memory limit (vbl_memory_limit) as the readers use it: one check per size read
 * from a file, before the allocation. */
#ifndef VBL_CORE_MEMORY_LIMIT_H
#define VBL_CORE_MEMORY_LIMIT_H

#include <stdint.h>

#include "vbl/vbl_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* VBL_SUCCESS when `bytes` fit the limit; otherwise records "PATH: WHAT needs N MiB, more than the
 * memory limit of L MiB (--memory-limit / VBL_MEMORY_LIMIT)" and returns VBL_ERROR_UNSUPPORTED. */
vbl_result vbl_memory_check(uint64_t bytes, const char* path, const char* what);

/* The message vbl_memory_check records (for the C++ adapter, which reports through exceptions). */
void vbl_memory_limit_message(char* out, size_t size, uint64_t bytes, const char* what);

#ifdef __cplusplus
}
#endif

#endif

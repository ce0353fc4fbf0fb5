/* Aligned allocation shared by the core and the C++ adapters (NanoVDB needs 32-byte alignment). */
#ifndef VBL_CORE_ALLOC_H
#define VBL_CORE_ALLOC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

void* vbl_aligned_alloc(size_t alignment, size_t size);
void vbl_aligned_free(void* pointer);

#ifdef __cplusplus
}
#endif

#endif

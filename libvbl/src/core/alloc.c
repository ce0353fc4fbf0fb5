/* Aligned allocation: posix_memalign underneath. */
#define _POSIX_C_SOURCE 200809L
#include "core/alloc.h"

#include <stdlib.h>

void* vbl_aligned_alloc(size_t alignment, size_t size)
{
    void* pointer = NULL;
    if (alignment < sizeof(void*)) alignment = sizeof(void*);
    if (posix_memalign(&pointer, alignment, size ? size : 1) != 0) return NULL;
    return pointer;
}

void vbl_aligned_free(void* pointer) { free(pointer); }

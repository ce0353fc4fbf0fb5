/* Per-thread work counts (work_count.h). */
#include "core/work_count.h"

static _Thread_local uint64_t vbl_thread_work[VBL_WORK_KIND_COUNT];

void vbl_work_add(vbl_work_kind kind, uint64_t n) { vbl_thread_work[kind] += n; }

uint64_t vbl_work_count(vbl_work_kind kind) { return vbl_thread_work[kind]; }

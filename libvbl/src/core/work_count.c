/* Per-thread work counts (work_count.h). */
#include "core/work_count.h"

_Thread_local uint64_t vbl_thread_work[VBL_WORK_KIND_COUNT];

/* Internal error reporting: record a result and a message for the calling thread. */
#ifndef VBL_CORE_ERROR_H
#define VBL_CORE_ERROR_H

#include "vbl/vbl_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Records `fmt` (printf style) as the calling thread's error message and returns `result`,
 * so a failing function can `return vbl_error(VBL_ERROR_SCENE, "%s: field 'x' ...", path);`. */
#define vbl_error vbl_report_error

#ifdef __cplusplus
}
#endif

#endif

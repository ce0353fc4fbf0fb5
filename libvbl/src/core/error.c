/* Per-thread error messages and result names. */
#include "core/error.h"

#include <stdarg.h>
#include <stdio.h>

static _Thread_local char vbl_error_message_buffer[2048];

vbl_result vbl_report_error(vbl_result result, const char* fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    vsnprintf(vbl_error_message_buffer, sizeof vbl_error_message_buffer, fmt, args);
    va_end(args);
    return result;
}

const char* vbl_last_error_message(void) { return vbl_error_message_buffer; }

void vbl_clear_error(void) { vbl_error_message_buffer[0] = '\0'; }

const char* vbl_result_name(vbl_result result)
{
    switch (result) {
    case VBL_SUCCESS: return "VBL_SUCCESS";
    case VBL_ERROR_INVALID_ARGUMENT: return "VBL_ERROR_INVALID_ARGUMENT";
    case VBL_ERROR_OUT_OF_MEMORY: return "VBL_ERROR_OUT_OF_MEMORY";
    case VBL_ERROR_FILE_NOT_FOUND: return "VBL_ERROR_FILE_NOT_FOUND";
    case VBL_ERROR_FILE_IO: return "VBL_ERROR_FILE_IO";
    case VBL_ERROR_CORRUPT_FILE: return "VBL_ERROR_CORRUPT_FILE";
    case VBL_ERROR_UNSUPPORTED: return "VBL_ERROR_UNSUPPORTED";
    case VBL_ERROR_GRID_NOT_FOUND: return "VBL_ERROR_GRID_NOT_FOUND";
    case VBL_ERROR_GRID_TYPE: return "VBL_ERROR_GRID_TYPE";
    case VBL_ERROR_BAD_VOXELS: return "VBL_ERROR_BAD_VOXELS";
    case VBL_ERROR_SCENE: return "VBL_ERROR_SCENE";
    case VBL_ERROR_INTERRUPTED: return "VBL_ERROR_INTERRUPTED";
    case VBL_ERROR_INTERNAL: return "VBL_ERROR_INTERNAL";
    }
    return "VBL_ERROR_UNKNOWN";
}

const char* vbl_version_string(void) { return VBL_VERSION_STRING; }

void vbl_version(int* major, int* minor, int* patch)
{
    if (major) *major = VBL_VERSION_MAJOR;
    if (minor) *minor = VBL_VERSION_MINOR;
    if (patch) *patch = VBL_VERSION_PATCH;
}

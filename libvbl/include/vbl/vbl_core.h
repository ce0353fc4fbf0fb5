/* libvbl core API: versions, result codes, error messages, handles' lifecycle conventions.
 *
 * Conventions (in the style of OpenEXRCore and Embree):
 *  - every fallible call returns a vbl_result; VBL_SUCCESS is 0;
 *  - on failure, vbl_last_error_message() returns one line naming the file/field at fault;
 *    the message is per calling thread and stays until the next failing call on that thread;
 *  - objects are opaque, reference counted handles: *_retain / *_release;
 *  - option structs start with a `size` field and have a *_DEFAULT initializer macro.
 * The library never prints and never exits the process. */
#ifndef VBL_CORE_H
#define VBL_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "vbl/vbl_version.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define VBL_API __declspec(dllexport)
#elif defined(__GNUC__)
#define VBL_API __attribute__((visibility("default")))
#else
#define VBL_API
#endif

/* What a fallible call returns; vbl_last_error_message() says more about a failure. */
typedef enum vbl_result {
    VBL_SUCCESS = 0,                /* the call did what it was asked */
    VBL_ERROR_INVALID_ARGUMENT = 1, /* a parameter is out of range or NULL */
    VBL_ERROR_OUT_OF_MEMORY = 2,    /* an allocation failed */
    VBL_ERROR_FILE_NOT_FOUND = 3,   /* a file does not exist or cannot be opened */
    VBL_ERROR_FILE_IO = 4,          /* read/write failure, full disk, unwritable path */
    VBL_ERROR_CORRUPT_FILE = 5,     /* not a VDB/NanoVDB/JSON file, truncated, bad checksum */
    VBL_ERROR_UNSUPPORTED = 6,      /* valid input this build cannot handle (codec, version) */
    VBL_ERROR_GRID_NOT_FOUND = 7,   /* no grid of that name/index; message lists the grids */
    VBL_ERROR_GRID_TYPE = 8,        /* the grid is not a float grid */
    VBL_ERROR_BAD_VOXELS = 9,       /* NaN, Inf or negative voxel values */
    VBL_ERROR_SCENE = 10,           /* malformed scene: message names file and field */
    VBL_ERROR_INTERRUPTED = 11,     /* cancelled by the caller */
    VBL_ERROR_INTERNAL = 12         /* a bug: please report */
} vbl_result;

/* Stable name of a result code, e.g. "VBL_ERROR_FILE_NOT_FOUND". */
VBL_API const char* vbl_result_name(vbl_result result);

/* The message of the last failure on the calling thread ("" if none). */
VBL_API const char* vbl_last_error_message(void);

/* Records a failure for the calling thread (printf-style message naming the file/field at
 * fault) and returns `result`. For plug-ins and adapters that report through libvbl's channel. */
VBL_API vbl_result vbl_report_error(vbl_result result, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Clears the calling thread's error message. */
VBL_API void vbl_clear_error(void);

/* Memory limit (issue 18). Every size read from a file (VDB grid and chunk sizes, NanoVDB
 * segments, EXR data windows, mesh counts) and every film is checked against it before the
 * allocation: an input that needs more fails with VBL_ERROR_UNSUPPORTED and a message naming the
 * file, the field and the limit, instead of taking what the machine grants. The default is
 * VBL_MEMORY_LIMIT from the environment when set (vbl_parse_memory_size's syntax), otherwise 3/4
 * of the physical memory (at least 256 MiB). Process-wide; safe to call from any thread. */
VBL_API uint64_t vbl_memory_limit(void);
/* Sets the limit in bytes; 0 restores the default. Values under 64 KiB are INVALID_ARGUMENT. */
VBL_API vbl_result vbl_set_memory_limit(uint64_t bytes);
/* Parses "4G", "512MiB", "1.5GB", "2000000000" (bytes), "50%" (of physical memory); K/M/G/T are
 * powers of 1024 with or without "B"/"iB". INVALID_ARGUMENT (message quoting `text`) otherwise. */
VBL_API vbl_result vbl_parse_memory_size(const char* text, uint64_t* out_bytes);

/* Runtime version (compare with the VBL_VERSION_* macros of the header you built with). */
VBL_API const char* vbl_version_string(void);
VBL_API void vbl_version(int* major, int* minor, int* patch);

#ifdef __cplusplus
}
#endif

#endif /* VBL_CORE_H */

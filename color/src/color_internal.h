/* Internals of vbl_color: the shipped config's text, compiled in (color_builtin_config.cc). */
#ifndef VBL_COLOR_INTERNAL_H
#define VBL_COLOR_INTERNAL_H

#ifdef __cplusplus
extern "C" {
#endif

const char* vbl_color_builtin_config_text(void);

#ifdef __cplusplus
}
#endif

#endif

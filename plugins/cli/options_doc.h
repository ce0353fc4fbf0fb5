/* Text of the render options table for people: the `vbl render --help` lines and the Markdown
 * table of `vbl options --markdown` (docs/readme/options_table.md), both from the library's
 * reflection calls (vbl/vbl_render_options.h). */
#ifndef VBL_CLI_OPTIONS_DOC_H
#define VBL_CLI_OPTIONS_DOC_H

#include <stddef.h>
#include <stdio.h>

#include <vbl/vbl.h>

/* The value a flag takes: "N", "X", "on|off", "pt|vpl|vrl|vbl|beams" (without a ZERO_DEFAULT choice 0). */
void vbl_options_doc_metavar(const vbl_render_option_info* d, char* out, size_t size);
/* "[1, 1000000000]", "(0, 1)", "[0, inf)"; enums and bools: "". */
void vbl_options_doc_range(const vbl_render_option_info* d, char* out, size_t size);
/* The default as vbl_render_option_get writes it. */
void vbl_options_doc_default(const vbl_render_option_info* d, char* out, size_t size);
/* The render-option lines of `vbl render --help`: every option with a flag. */
void vbl_options_doc_help(FILE* out);
/* The Markdown table of every option. */
void vbl_options_doc_markdown(FILE* out);

#endif

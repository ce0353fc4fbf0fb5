/* `vbl options [--markdown]`: the render options table (docs/readme/options_table.md). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "options_doc.h"

int vbl_cmd_options(int argc, char** argv)
{
    int markdown = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--markdown")) {
            markdown = 1;
        } else if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            printf("usage: vbl options [--markdown]\n\n"
                   "Lists every render option: its scene-file key, `vbl render` flag, range, default and\n"
                   "meaning (--markdown: the table of docs/readme/options_table.md).\n");
            return VBL_EXIT_OK;
        } else {
            fprintf(stderr, "vbl options: unknown option '%s' (see 'vbl options --help')\n", argv[i]);
            return VBL_EXIT_USAGE;
        }
    }
    if (markdown) vbl_options_doc_markdown(stdout);
    else vbl_options_doc_help(stdout);
    return VBL_EXIT_OK;
}

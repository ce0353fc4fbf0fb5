/* `vbl render` (placeholder until its issue lands). */
#include <stdio.h>

#include "cli.h"

int vbl_cmd_render(int argc, char** argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "vbl: 'render' is not implemented yet\n");
    return VBL_EXIT_FAILURE;
}

/* `vbl info` (placeholder until its issue lands). */
#include <stdio.h>

#include "cli.h"

int vbl_cmd_info(int argc, char** argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "vbl: 'info' is not implemented yet\n");
    return VBL_EXIT_FAILURE;
}

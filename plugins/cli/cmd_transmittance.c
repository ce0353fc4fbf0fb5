/* `vbl transmittance` (placeholder until its issue lands). */
#include <stdio.h>

#include "cli.h"

int vbl_cmd_transmittance(int argc, char** argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "vbl: 'transmittance' is not implemented yet\n");
    return VBL_EXIT_FAILURE;
}

/* Placeholder majorant grid (replaced by the volume core). */
#include "volume/volume.h"

#include <string.h>

vbl_result vbl_majorant_grid_build(vbl_majorant_grid* grid, const vbl_volume* volume, int block)
{
    (void)volume;
    memset(grid, 0, sizeof *grid);
    grid->block = block;
    return VBL_SUCCESS;
}

void vbl_majorant_grid_free(vbl_majorant_grid* grid) { (void)grid; }

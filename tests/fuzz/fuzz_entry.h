/* Entry points shared by the fuzz targets (libFuzzer, tests/fuzz/fuzz_*.c) and the corpus replay
 * driver: each writes the input to a private temporary file (the loaders read files) with the
 * extension the format needs and runs the loader the `vbl` command uses on it. They never fail:
 * the point is that no input crashes, hangs or leaks (ASan/UBSan/LSan builds). */
#ifndef VBL_FUZZ_ENTRY_H
#define VBL_FUZZ_ENTRY_H

#include <stddef.h>
#include <stdint.h>

/* .vdb / .nvdb: vbl_volume_load and vbl_file_list_grids (the file kind comes from its magic). */
void vbl_fuzz_volume(const uint8_t* data, size_t size);
/* scene JSON: vbl_scene_load. */
void vbl_fuzz_scene(const uint8_t* data, size_t size);
/* EXR: vbl_exr_read (merge, resume, diff, preview read EXRs this way). */
void vbl_fuzz_exr(const uint8_t* data, size_t size);
/* meshes: vbl_mesh_load as .ply when the input starts with "ply", else as .obj. */
void vbl_fuzz_mesh(const uint8_t* data, size_t size);

#endif

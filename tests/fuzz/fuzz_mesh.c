/* libFuzzer target: vbl_fuzz_mesh (fuzz_entry.h). Without libFuzzer, replay_main.c drives it. */
#include <stddef.h>
#include <stdint.h>

#include "fuzz_entry.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    vbl_fuzz_mesh(data, size);
    return 0;
}

/* Fuzz target "scene": the JSON scene loader (kg_scene_parse) on arbitrary bytes, then
 * the scene it accepts, instantiated and stepped. Needs kgyro_io. The contracts checked
 * are those of scene_contracts.h; a scene file names no other file, so a refusal is
 * always a parse error. */
#include "scene_contracts.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    fuzz_parse_scene(data, size, "fuzz.json", "fuzz.json: ", 0);
    return 0;
}

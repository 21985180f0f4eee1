/* Fuzz target "tiled": the Tiled map loader (a Tiled JSON map given to kg_scene_parse
 * is read as a map: tile layers, tilesets, object layers), then the scene it makes,
 * instantiated and stepped with its tile maps. Needs kgyro_io. The contracts checked
 * are those of scene_contracts.h.
 *
 * The map is named tests/data/tiled/fuzz.tmj, so that the external tilesets the seed
 * maps name (terrain.tsj) are found beside it; a tileset the fuzzer makes up may be
 * missing, hence KG_ERROR_IO is an accepted refusal, and a message may name the tileset
 * rather than the map. Both scripts/fuzz.sh and the replaying ctest run from the
 * repository root. */
#include "scene_contracts.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    fuzz_parse_scene(data, size, "tests/data/tiled/fuzz.tmj", "tests/data/tiled/", 1);
    return 0;
}

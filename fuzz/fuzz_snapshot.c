/* Fuzz target "snapshot": the snapshot reader (kg_world_restore) on arbitrary bytes. The
 * first byte picks how: even, the rest as they come (the header and checksum checks);
 * odd, the rest with its checksum made right (kg_snapshot_reseal), so that mutated
 * contents reach the checks behind it. A world like the seeds' (fuzz/corpus/snapshot,
 * written by this file built with FUZZ_SNAPSHOT_WRITE_SEEDS) takes them. Contracts: a
 * refusal is one of the documented codes with a message, and leaves the world exactly
 * as it was (its own snapshot unchanged); a snapshot taken in steps without a crash. */
#include "fuzz_common.h"
#include "core/snapshot_io.h"
#include "kgyro/kgyro.h"

static void fuzz_push(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    (void)user_data;
    for (int i = 0; i < count; ++i) {
        kg_body_apply_force_to_center(world, bodies[i], (kg_vec2){0.5f, 0.0f});
    }
}

/* The world every input is restored into: 64 bodies at most, a user applicator first. */
static kg_world* fuzz_world(void)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.max_bodies = 64;
    kg_world* world = NULL;
    FUZZ_REQUIRE(kg_create_world(&def, &world) == KG_OK, "the fuzz world is created");
    kg_body none = KG_NULL_BODY_INIT;
    kg_applicator user;
    FUZZ_REQUIRE(kg_add_force_applicator(world, fuzz_push, &none, 1, NULL, &user) == KG_OK, "its applicator is added");
    return world;
}

static void* fuzz_snapshot_of(kg_world* world, size_t* size)
{
    FUZZ_REQUIRE(kg_world_snapshot_size(world, size) == KG_OK, "a snapshot's size is known");
    void* buffer = malloc(*size);
    size_t written = 0;
    FUZZ_REQUIRE(buffer && kg_world_snapshot(world, buffer, *size, &written) == KG_OK && written == *size,
                 "a snapshot is taken");
    return buffer;
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    int reseal = size > 0 && (data[0] & 1u);
    size_t n = size > 0 ? size - 1 : 0;
    unsigned char* bytes = malloc(n + 1);
    memcpy(bytes, data + (size > 0), n);
    if (reseal) {
        kg_snapshot_reseal(bytes, n);
    }
    kg_world* world = fuzz_world();
    size_t before_size = 0;
    void* before = fuzz_snapshot_of(world, &before_size);
    kg_result r = kg_world_restore(world, bytes, n);
    if (r == KG_OK) {
        for (int i = 0; i < 3; ++i) {
            kg_world_step(world, 1.0f / 60.0f);
        }
    } else {
        FUZZ_REQUIRE(r == KG_ERROR_INVALID_ARGUMENT || r == KG_ERROR_UNSUPPORTED || r == KG_ERROR_OUT_OF_MEMORY,
                     "a refusal has a documented code");
        FUZZ_REQUIRE(kg_last_error()[0] != '\0', "a refusal says why");
        size_t after_size = 0;
        void* after = fuzz_snapshot_of(world, &after_size);
        FUZZ_REQUIRE(after_size == before_size && memcmp(after, before, before_size) == 0,
                     "a refused snapshot leaves the world as it was");
        free(after);
    }
    free(before);
    free(bytes);
    kg_destroy_world(world);
    return 0;
}

#ifdef FUZZ_SNAPSHOT_WRITE_SEEDS
/* Writes the seeds into the directory named: snapshots of a small scene after 0, 20 and
 * 60 steps (a tile map, each shape kind, a wind, a hinge and a rod), each behind a mode
 * byte of 1. */
int main(int argc, char** argv)
{
    if (argc < 2) {
        return 2;
    }
    kg_world* world = fuzz_world();
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    uint16_t tiles[16] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    kg_tilemap_def map = kg_default_tilemap_def();
    map.width = 16;
    map.height = 1;
    map.origin = (kg_vec2){-8.0f, -1.0f};
    map.shapes = shapes;
    map.shape_count = 2;
    map.tiles = tiles;
    kg_tilemap handle;
    FUZZ_REQUIRE(kg_create_tilemap(world, &map, &handle) == KG_OK, "the map is made");
    kg_vec2 tri[3] = {{-0.2f, 0.0f}, {0.2f, 0.0f}, {0.0f, 0.3f}};
    kg_shape_def kinds[4] = {kg_box_shape(0.4f, 0.3f), kg_circle_shape(0.2f),
                             kg_capsule_shape((kg_vec2){-0.1f, 0.0f}, (kg_vec2){0.1f, 0.0f}, 0.1f),
                             kg_polygon_shape(tri, 3)};
    kg_body bodies[12];
    for (int i = 0; i < 12; ++i) {
        kg_body_def def = kg_default_body_def();
        def.position = (kg_vec2){-2.0f + 0.45f * (float)i, 0.5f + 0.2f * (float)(i % 3)};
        def.shape = kinds[i % 4];
        FUZZ_REQUIRE(kg_create_body(world, &def, &bodies[i]) == KG_OK, "a body is made");
    }
    kg_applicator wind;
    FUZZ_REQUIRE(kg_add_wind_applicator(world, (kg_vec2){1.0f, 0.0f}, 1.0f, 0.1f, bodies, 4, &wind) == KG_OK,
                 "the wind is added");
    kg_revolute_joint_def hinge = kg_default_revolute_joint_def();
    hinge.base.body_a = bodies[0];
    hinge.base.body_b = bodies[1];
    hinge.local_anchor_a = (kg_vec2){0.225f, 0.0f};
    hinge.local_anchor_b = (kg_vec2){-0.225f, -0.2f};
    FUZZ_REQUIRE(kg_create_revolute_joint(world, &hinge, NULL) == KG_OK, "a hinge is made");
    kg_distance_joint_def rope = kg_default_distance_joint_def();
    rope.base.body_b = bodies[5];
    rope.local_anchor_a = (kg_vec2){0.0f, 3.0f};
    rope.length = 2.5f;
    FUZZ_REQUIRE(kg_create_distance_joint(world, &rope, NULL) == KG_OK, "a rope is made");
    int steps[3] = {0, 20, 60};
    for (int k = 0, done = 0; k < 3; ++k) {
        for (; done < steps[k]; ++done) {
            kg_world_step(world, 1.0f / 60.0f);
        }
        size_t size = 0;
        void* snap = fuzz_snapshot_of(world, &size);
        char path[512];
        snprintf(path, sizeof path, "%s/steps_%d", argv[1], steps[k]);
        FILE* f = fopen(path, "wb");
        FUZZ_REQUIRE(f != NULL, "the seed file opens");
        fputc(1, f);
        fwrite(snap, 1, size, f);
        fclose(f);
        free(snap);
    }
    kg_destroy_world(world);
    return 0;
}
#endif

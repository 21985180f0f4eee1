/* Tile-map benchmark: the cost of a step with 10,000 bodies falling onto tile terrain, for
 * a 256 x 256 map and a 4096 x 4096 map holding the same terrain pattern (so the bodies
 * meet exactly the same tiles and the two runs are the same simulation), and for the
 * 256 x 256 terrain built as one static polygon body per solid tile.
 *
 *   bench_tilemap [measured_steps]   (default 120, after 300 warm-up steps: 5 s, by when
 *                                     the bodies have landed)
 *
 * The three worlds are stepped in turn, step by step, so a busy machine slows them alike.
 * Prints per world the median step time and the median time of the collision stage (body
 * pairs and tiles together), in milliseconds, and the contact count at the end; then the
 * tile collision alone (kg_tilemap_collide on the final state, repeated) for both maps. */
#define _POSIX_C_SOURCE 200809L

#include "bench_util.h"
#include "collide/tilemap.h"
#include "kgyro/kgyro.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BODY_COLUMNS 100
#define BODY_ROWS 100
#define WARMUP_STEPS 300
#define TILE_PASSES 200
#define WORLD_COUNT 3
#define DT (1.0f / 60.0f)

enum { EMPTY, BOX, SLOPE_UP, SLOPE_DOWN, HALF, PLATFORM, SHAPE_COUNT };

/* The terrain repeats every 32 x 32 tiles above a solid ground 4 tiles deep: a floating
 * block, a ramp up and down, a run of half tiles and a one-way platform. */
static int terrain_tile(int x, int y)
{
    if (y < 4) {
        return BOX;
    }
    int u = x % 32, v = y % 32;
    if (v == 10 && u >= 4 && u < 12) {
        return BOX;
    }
    if (v == 4 && u >= 14 && u < 17) {
        return u == 14 ? SLOPE_UP : (u == 16 ? SLOPE_DOWN : BOX);
    }
    if (v == 4 && u >= 20 && u < 28) {
        return HALF;
    }
    return v == 20 && u >= 16 && u < 28 ? PLATFORM : EMPTY;
}

static void standard_shapes(kg_tile_shape* shapes)
{
    shapes[EMPTY] = kg_tile_empty();
    shapes[BOX] = kg_tile_box();
    shapes[SLOPE_UP] = kg_tile_slope(KG_TILE_BOTTOM_RIGHT);
    shapes[SLOPE_DOWN] = kg_tile_slope(KG_TILE_BOTTOM_LEFT);
    shapes[HALF] = kg_tile_half(KG_TILE_SIDE_BOTTOM);
    shapes[PLATFORM] = kg_tile_platform();
}

static kg_world* make_world(void)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.max_bodies = 40000;
    kg_world* world = NULL;
    if (kg_create_world(&def, &world) != KG_OK) {
        fprintf(stderr, "bench_tilemap: %s\n", kg_last_error());
        exit(1);
    }
    return world;
}

static void add_tilemap(kg_world* world, int side)
{
    uint16_t* tiles = malloc((size_t)side * (size_t)side * sizeof *tiles);
    if (!tiles) {
        fprintf(stderr, "bench_tilemap: out of memory\n");
        exit(1);
    }
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            tiles[(size_t)y * (size_t)side + (size_t)x] = (uint16_t)terrain_tile(x, y);
        }
    }
    kg_tile_shape shapes[SHAPE_COUNT];
    standard_shapes(shapes);
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = side;
    def.height = side;
    def.shapes = shapes;
    def.shape_count = SHAPE_COUNT;
    def.tiles = tiles;
    kg_tilemap map;
    if (kg_create_tilemap(world, &def, &map) != KG_OK) {
        fprintf(stderr, "bench_tilemap: %s\n", kg_last_error());
        exit(1);
    }
    free(tiles);
}

/* One static polygon body per solid tile, one-way platforms included (as solid tiles:
 * static bodies cannot be one-way). Returns how many. */
static int add_static_terrain(kg_world* world, int side)
{
    kg_tile_shape shapes[SHAPE_COUNT];
    standard_shapes(shapes);
    int count = 0;
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const kg_tile_shape* s = &shapes[terrain_tile(x, y)];
            if (s->type != KG_TILE_SHAPE_POLYGON) {
                continue;
            }
            kg_body_def bd = kg_default_body_def();
            bd.type = KG_BODY_STATIC;
            bd.shape = kg_polygon_shape(s->vertices, s->count);
            bd.position = (kg_vec2){(float)x, (float)y};
            kg_body body;
            if (kg_create_body(world, &bd, &body) != KG_OK) {
                fprintf(stderr, "bench_tilemap: %s\n", kg_last_error());
                exit(1);
            }
            count++;
        }
    }
    return count;
}

/* 10,000 boxes and circles of 0.3 to 0.6 m on a 2 m x 1.2 m grid from (2, 6). */
static void add_bodies(kg_world* world)
{
    uint32_t rng = 7u;
    for (int row = 0; row < BODY_ROWS; ++row) {
        for (int column = 0; column < BODY_COLUMNS; ++column) {
            rng = rng * 1664525u + 1013904223u;
            float size = 0.3f + 0.3f * (float)(rng >> 8) * (1.0f / 16777216.0f);
            kg_body_def bd = kg_default_body_def();
            bd.shape = (row + column) % 2 ? kg_box_shape(size, size) : kg_circle_shape(0.5f * size);
            bd.position = (kg_vec2){2.0f + 2.0f * (float)column, 6.0f + 1.2f * (float)row};
            kg_body body;
            if (kg_create_body(world, &bd, &body) != KG_OK) {
                fprintf(stderr, "bench_tilemap: %s\n", kg_last_error());
                exit(1);
            }
        }
    }
}

static double stage_ms(const kg_world* world, const char* name)
{
    kg_stage_times times;
    kg_world_get_stage_times(world, &times);
    for (int i = 0; i < times.count; ++i) {
        if (strcmp(times.names[i], name) == 0) {
            return times.ms[i];
        }
    }
    return 0.0;
}

typedef struct bench_world {
    char name[64];
    kg_world* world;
    double setup_ms;
    double* step_ms;
    double* collide_ms;
} bench_world;

static void* checked_malloc(size_t size)
{
    void* p = malloc(size);
    if (!p) {
        fprintf(stderr, "bench_tilemap: out of memory\n");
        exit(1);
    }
    return p;
}

static void make_tiled(bench_world* b, int side)
{
    double start = bench_now_ms();
    b->world = make_world();
    add_tilemap(b->world, side);
    add_bodies(b->world);
    b->setup_ms = bench_now_ms() - start;
    snprintf(b->name, sizeof b->name, "tile map %d x %d", side, side);
}

static void make_static(bench_world* b, int side)
{
    double start = bench_now_ms();
    b->world = make_world();
    int statics = add_static_terrain(b->world, side);
    add_bodies(b->world);
    b->setup_ms = bench_now_ms() - start;
    snprintf(b->name, sizeof b->name, "static bodies (%d) %d x %d", statics, side, side);
}

/* Median time of kg_tilemap_collide over the world's current state, in ms. */
static double tile_collide_ms(bench_world* b)
{
    int room = 4 * BODY_COLUMNS * BODY_ROWS;
    kg_contact* out = checked_malloc((size_t)room * sizeof *out);
    double* ms = checked_malloc(TILE_PASSES * sizeof *ms);
    int found = 0;
    for (int i = 0; i < TILE_PASSES; ++i) {
        double start = bench_now_ms();
        found = kg_tilemap_collide(b->world, out, room, NULL, 0);
        ms[i] = bench_now_ms() - start;
    }
    double result = bench_median(ms, TILE_PASSES);
    printf("%-34s %12.3f %14d\n", b->name, result, found);
    free(out);
    free(ms);
    return result;
}

int main(int argc, char** argv)
{
    int steps = argc > 1 ? atoi(argv[1]) : 120;
    if (steps < 1) {
        fprintf(stderr, "usage: bench_tilemap [measured_steps]\n");
        return 2;
    }
    bench_world worlds[WORLD_COUNT];
    make_tiled(&worlds[0], 256);
    make_tiled(&worlds[1], 4096);
    make_static(&worlds[2], 256);
    for (int w = 0; w < WORLD_COUNT; ++w) {
        worlds[w].step_ms = checked_malloc((size_t)steps * sizeof(double));
        worlds[w].collide_ms = checked_malloc((size_t)steps * sizeof(double));
    }
    for (int i = 0; i < WARMUP_STEPS + steps; ++i) {
        for (int w = 0; w < WORLD_COUNT; ++w) {
            double start = bench_now_ms();
            kg_world_step(worlds[w].world, DT);
            if (i >= WARMUP_STEPS) {
                worlds[w].step_ms[i - WARMUP_STEPS] = bench_now_ms() - start;
                worlds[w].collide_ms[i - WARMUP_STEPS] = stage_ms(worlds[w].world, "collide");
            }
        }
    }
    printf("10,000 bodies falling onto tile terrain; %d steps measured after %d; median ms per step\n", steps,
           WARMUP_STEPS);
    printf("%-34s %9s %11s %12s %9s\n", "terrain", "setup ms", "step ms", "collide ms", "contacts");
    for (int w = 0; w < WORLD_COUNT; ++w) {
        bench_world* b = &worlds[w];
        printf("%-34s %9.1f %11.3f %12.3f %9d\n", b->name, b->setup_ms, bench_median(b->step_ms, steps),
               bench_median(b->collide_ms, steps), kg_world_contact_count(b->world));
    }
    printf("\ntile collision alone on the final state, median of %d passes\n", TILE_PASSES);
    printf("%-34s %12s %14s\n", "terrain", "tiles ms", "tile contacts");
    tile_collide_ms(&worlds[0]);
    tile_collide_ms(&worlds[1]);
    for (int w = 0; w < WORLD_COUNT; ++w) {
        free(worlds[w].step_ms);
        free(worlds[w].collide_ms);
        kg_destroy_world(worlds[w].world);
    }
    return 0;
}

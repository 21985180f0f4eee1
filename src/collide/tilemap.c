/* Tile maps: storage, the public API, the exposed-edge flags, and the collision of moving
 * bodies with the cells their bounds cover. The data layout is in collide/tilemap.h, the
 * per-cell collision in collide/tile_collide.h. */
#include "collide/tilemap.h"
#include "collide/aabb.h"
#include "collide/tile_shape.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/snapshot_io.h"

#include <math.h>
#include <string.h>

#define KG_MAX_TILEMAP_CELLS (1 << 28)
#define KG_MAX_TILEMAP_SIDE 65536
/* Keys are 32 bits and KG_NULL_INDEX (all ones) means "no tile". */
#define KG_KEY_SPACE 0xFFFFFFFFull

typedef struct kg_map {
    kg_u32 generation;  /* odd while alive */
    kg_tilemap_def def; /* shapes and tiles NULL */
    kg_tile_template* templates; /* def.shape_count */
    kg_u32* cells;      /* layer_count * height * width words, in kg_tilemaps.cells */
    kg_u32 key_base;
    kg_u32 key_count;
    int cells_dirty;    /* set_tile changed cells since the OpenCL backend last looked */
} kg_map;

struct kg_tilemaps {
    kg_map* maps;
    int map_count; /* slots used, live or not */
    int map_capacity;
    int* order;    /* live slots by key_base */
    int live_count;
    /* The live maps as the tile pass reads them (collide/tile_pass.h), in key order: a
     * description each (map_capacity), their cells and protos one map after the other. */
    kg_tile_map_info* infos;
    kg_u32* cells;
    kg_tile_proto* protos;
    size_t cell_count, proto_count;
    kg_u32 layout_version; /* bumped when a map is created or destroyed */
    /* body origins at the last collision, for one-way platforms; generation 0 = unknown */
    kg_vec2* last_origin;
    kg_u32* last_generation;
};

static int kg_map_alive(const kg_map* m) { return (m->generation & 1u) != 0u; }

/* ---- handles ---- */

static kg_map* kg_resolve_map(const kg_world* world, kg_tilemap handle)
{
    struct kg_tilemaps* t = world ? world->tilemaps : NULL;
    if (!t || handle.index >= (uint32_t)t->map_count || !kg_map_alive(&t->maps[handle.index]) ||
        t->maps[handle.index].generation != handle.generation) {
        kg_fail(KG_ERROR_INVALID_HANDLE, "tile map handle {%u, %u} is stale or invalid", handle.index,
                handle.generation);
        return NULL;
    }
    return &t->maps[handle.index];
}

static int kg_map_cell_count(const kg_map* m) { return m->def.width * m->def.height; }

static kg_u32 kg_cell_index(const kg_map* m, int layer, int x, int y)
{
    return (kg_u32)((layer * m->def.height + y) * m->def.width + x);
}

static const kg_tile_template* kg_template_at(const kg_map* m, int layer, int x, int y)
{
    if (x < 0 || y < 0 || x >= m->def.width || y >= m->def.height) {
        return NULL;
    }
    return &m->templates[kg_cell_id(m->cells[kg_cell_index(m, layer, x, y)])];
}

/* ---- exposed-edge flags ---- */

/* The span [lo, hi] of a template's edge on the given cell side, along that side. */
static int kg_side_span(const kg_tile_template* t, int side, float* lo, float* hi)
{
    int n = t->proto.shape.count;
    for (int i = 0; i < n; ++i) {
        kg_vec2 a = t->unit[i], b = t->unit[(i + 1) % n];
        if (kg_tile_edge_side(a, b) == side) {
            float ua = side % 2 == 0 ? a.x : a.y, ub = side % 2 == 0 ? b.x : b.y;
            *lo = fminf(ua, ub);
            *hi = fmaxf(ua, ub);
            return 1;
        }
    }
    return 0;
}

/* Whether [lo, hi] covers the part of a side just after u, going up (towards +1) or down. */
static int kg_covered_near(float u, int up, float lo, float hi)
{
    const float tolerance = KG_TILE_WELD;
    return up ? lo <= u + tolerance && hi > u + tolerance : lo < u - tolerance && hi >= u - tolerance;
}

static const int kSideDx[4] = {0, 1, 0, -1};
static const int kSideDy[4] = {-1, 0, 1, 0};

/* The exposure bits of edge i of the tile at (layer, x, y), given its neighbours. */
static kg_u32 kg_edge_exposure(const kg_map* m, int layer, int x, int y, const kg_tile_template* t, int i)
{
    kg_u32 both = (1u << (KG_CELL_START_SHIFT + (kg_u32)i)) | (1u << (KG_CELL_END_SHIFT + (kg_u32)i));
    int n = t->proto.shape.count;
    if ((t->proto.flags & KG_TILE_FLAG_ONE_WAY) && !(t->proto.shape.normals[i].y > KG_TILE_ANGLE_TOLERANCE)) {
        return 0u;
    }
    kg_vec2 a = t->unit[i], b = t->unit[(i + 1) % n];
    int side = kg_tile_edge_side(a, b);
    if (side < 0) {
        return both;
    }
    const kg_tile_template* neighbour = kg_template_at(m, layer, x + kSideDx[side], y + kSideDy[side]);
    float lo, hi;
    if (!neighbour || !kg_tile_template_is_solid(neighbour) || !kg_side_span(neighbour, (side + 2) % 4, &lo, &hi)) {
        return both;
    }
    float ua = side % 2 == 0 ? a.x : a.y, ub = side % 2 == 0 ? b.x : b.y;
    kg_u32 bits = 0u;
    if (!kg_covered_near(ua, ub > ua, lo, hi)) {
        bits |= 1u << (KG_CELL_START_SHIFT + (kg_u32)i);
    }
    if (!kg_covered_near(ub, ua > ub, lo, hi)) {
        bits |= 1u << (KG_CELL_END_SHIFT + (kg_u32)i);
    }
    return bits;
}

/* Recomputes the exposure bits of one cell from its id and its four side neighbours. */
static void kg_refresh_cell(kg_map* m, int layer, int x, int y)
{
    if (x < 0 || y < 0 || x >= m->def.width || y >= m->def.height) {
        return;
    }
    kg_u32* word = &m->cells[kg_cell_index(m, layer, x, y)];
    kg_u32 id = kg_cell_id(*word);
    const kg_tile_template* t = &m->templates[id];
    kg_u32 bits = 0u;
    for (int i = 0; t->proto.shape.count >= 3 && i < t->proto.shape.count; ++i) {
        bits |= kg_edge_exposure(m, layer, x, y, t, i);
    }
    *word = id | bits;
}

static void kg_refresh_all(kg_map* m)
{
    for (int layer = 0; layer < m->def.layer_count; ++layer) {
        for (int y = 0; y < m->def.height; ++y) {
            for (int x = 0; x < m->def.width; ++x) {
                kg_refresh_cell(m, layer, x, y);
            }
        }
    }
}

/* ---- creating and destroying ---- */

kg_tilemap_def kg_default_tilemap_def(void)
{
    kg_tilemap_def def;
    memset(&def, 0, sizeof def);
    def.layer_count = 1;
    def.tile_size = kg_v2(1.0f, 1.0f);
    def.friction = 0.6f;
    def.category = 1u;
    def.mask = 0xFFFFFFFFu;
    return def;
}

static kg_result kg_validate_tilemap_def(const kg_tilemap_def* d)
{
    if (d->width < 1 || d->height < 1 || d->layer_count < 1 || d->width > KG_MAX_TILEMAP_SIDE ||
        d->height > KG_MAX_TILEMAP_SIDE ||
        (long long)d->width * d->height * d->layer_count > (long long)KG_MAX_TILEMAP_CELLS) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "tile map size %d x %d x %d layers: each side must be in [1, %d], and the cells of all "
                       "layers at most %d", d->width, d->height, d->layer_count, KG_MAX_TILEMAP_SIDE,
                       KG_MAX_TILEMAP_CELLS);
    }
    if (!isfinite(d->tile_size.x) || !isfinite(d->tile_size.y) || !(d->tile_size.x > 0.0f) ||
        !(d->tile_size.y > 0.0f) || !isfinite(d->origin.x) || !isfinite(d->origin.y)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile map tile size must be finite and > 0, origin finite");
    }
    if (!d->shapes || d->shape_count < 1 || d->shape_count > KG_MAX_TILE_ID + 1) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a tile map needs 1 to %d shapes (got %d)", KG_MAX_TILE_ID + 1,
                       d->shape_count);
    }
    if (d->shapes[0].type != KG_TILE_SHAPE_EMPTY) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile id 0 must be empty");
    }
    if (!isfinite(d->friction) || d->friction < 0.0f || !isfinite(d->restitution) || d->restitution < 0.0f ||
        d->restitution > 1.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile map friction must be >= 0 and restitution in [0, 1]");
    }
    return KG_OK;
}

static kg_result kg_build_templates(kg_map* m, const kg_tile_shape* shapes)
{
    m->templates = kg_alloc_zeroed((size_t)m->def.shape_count * sizeof *m->templates);
    if (!m->templates) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate %d tile shapes", m->def.shape_count);
    }
    for (int id = 0; id < m->def.shape_count; ++id) {
        if (kg_tile_template_build(&shapes[id], m->def.tile_size, &m->templates[id]) != KG_OK) {
            char reason[256];
            memcpy(reason, kg_last_error(), sizeof reason - 1);
            reason[sizeof reason - 1] = '\0';
            return kg_fail(kg_last_result(), "tile id %d: %s", id, reason);
        }
    }
    return KG_OK;
}

static kg_result kg_check_tiles(const kg_map* m, const uint16_t* tiles)
{
    for (kg_u32 i = 0; tiles && i < m->key_count; ++i) {
        if (tiles[i] >= m->def.shape_count) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile %u has id %u, but the map has %d shapes", (unsigned)i,
                           (unsigned)tiles[i], m->def.shape_count);
        }
    }
    return KG_OK;
}

/* The map's cells (zeros, placed by kg_place_maps) from its checked tile ids. */
static void kg_fill_cells(kg_map* m, const uint16_t* tiles)
{
    for (kg_u32 i = 0; tiles && i < m->key_count; ++i) {
        m->cells[i] = tiles[i];
    }
    kg_refresh_all(m);
}

static void kg_map_free(kg_map* m)
{
    kg_free(m->templates);
    m->templates = NULL;
    m->cells = NULL;
}

static void kg_describe_map(const kg_map* m, size_t cell_offset, size_t proto_offset, kg_tile_map_info* out)
{
    memset(out, 0, sizeof *out);
    out->origin = m->def.origin;
    out->tile_size = m->def.tile_size;
    out->width = m->def.width;
    out->height = m->def.height;
    out->layer_count = m->def.layer_count;
    out->cell_offset = (kg_u32)cell_offset;
    out->proto_offset = (kg_u32)proto_offset;
    out->key_base = m->key_base;
    out->friction = m->def.friction;
    out->restitution = m->def.restitution;
    out->category = m->def.category;
    out->mask = m->def.mask;
}

/* Lays the live maps out one after the other in key order into cells and protos, which
 * are new arrays (a map was added: it has no cells yet and gets zeros) or the current
 * ones (a map went: every map moves down, never up, so memmove is safe). */
static void kg_place_maps(struct kg_tilemaps* t, kg_u32* cells, kg_tile_proto* protos)
{
    size_t cell_at = 0, proto_at = 0;
    for (int i = 0; i < t->live_count; ++i) {
        kg_map* m = &t->maps[t->order[i]];
        if (m->cells) {
            memmove(cells + cell_at, m->cells, m->key_count * sizeof *cells);
        }
        m->cells = cells + cell_at;
        for (int id = 0; id < m->def.shape_count; ++id) {
            protos[proto_at + (size_t)id] = m->templates[id].proto;
        }
        kg_describe_map(m, cell_at, proto_at, &t->infos[i]);
        cell_at += m->key_count;
        proto_at += (size_t)m->def.shape_count;
    }
    t->cells = cells;
    t->protos = protos;
    t->cell_count = cell_at;
    t->proto_count = proto_at;
}

/* Places the live maps, one of them new, in arrays of their own size. */
static kg_result kg_place_new_map(struct kg_tilemaps* t)
{
    size_t cell_count = 0, proto_count = 0;
    for (int i = 0; i < t->live_count; ++i) {
        cell_count += t->maps[t->order[i]].key_count;
        proto_count += (size_t)t->maps[t->order[i]].def.shape_count;
    }
    kg_u32* cells = kg_alloc_zeroed(cell_count * sizeof *cells);
    kg_tile_proto* protos = kg_alloc_zeroed(proto_count * sizeof *protos);
    if (!cells || !protos) {
        kg_free(cells);
        kg_free(protos);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate %zu tile map cells", cell_count);
    }
    kg_u32* old_cells = t->cells;
    kg_tile_proto* old_protos = t->protos;
    kg_place_maps(t, cells, protos);
    kg_free(old_cells);
    kg_free(old_protos);
    return KG_OK;
}

static kg_result kg_tilemaps_create(kg_world* world)
{
    struct kg_tilemaps* t = kg_alloc_zeroed(sizeof *t);
    if (!t) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the tile maps");
    }
    t->last_origin = kg_alloc_zeroed((size_t)world->def.max_bodies * sizeof *t->last_origin);
    t->last_generation = kg_alloc_zeroed((size_t)world->def.max_bodies * sizeof *t->last_generation);
    world->tilemaps = t;
    if (!t->last_origin || !t->last_generation) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the tile maps");
    }
    return KG_OK;
}

void kg_tilemaps_destroy(kg_world* world)
{
    struct kg_tilemaps* t = world->tilemaps;
    if (!t) {
        return;
    }
    for (int i = 0; i < t->map_count; ++i) {
        kg_map_free(&t->maps[i]);
    }
    kg_free(t->maps);
    kg_free(t->order);
    kg_free(t->infos);
    kg_free(t->cells);
    kg_free(t->protos);
    kg_free(t->last_origin);
    kg_free(t->last_generation);
    kg_free(t);
    world->tilemaps = NULL;
}

/* A free slot (reused lowest first) with room in maps and order. */
static int kg_take_slot(struct kg_tilemaps* t)
{
    for (int i = 0; i < t->map_count; ++i) {
        if (!kg_map_alive(&t->maps[i])) {
            return i;
        }
    }
    if (t->map_count == t->map_capacity) {
        int capacity = t->map_capacity > 0 ? 2 * t->map_capacity : 4;
        kg_map* maps = kg_alloc_zeroed((size_t)capacity * sizeof *maps);
        int* order = kg_alloc_zeroed((size_t)capacity * sizeof *order);
        kg_tile_map_info* infos = kg_alloc_zeroed((size_t)capacity * sizeof *infos);
        if (!maps || !order || !infos) {
            kg_free(maps);
            kg_free(order);
            kg_free(infos);
            return -1;
        }
        if (t->map_count > 0) {
            memcpy(maps, t->maps, (size_t)t->map_count * sizeof *maps);
            memcpy(order, t->order, (size_t)t->live_count * sizeof *order);
        }
        kg_free(t->maps);
        kg_free(t->order);
        kg_free(t->infos); /* rewritten whole by kg_place_maps */
        t->maps = maps;
        t->order = order;
        t->infos = infos;
        t->map_capacity = capacity;
    }
    return t->map_count++;
}

/* Finds the lowest free range of key_count keys among the live maps (kept sorted by key
 * base) and inserts slot into the order there. */
static kg_result kg_assign_keys(struct kg_tilemaps* t, int slot)
{
    kg_map* m = &t->maps[slot];
    unsigned long long base = 0;
    int at = 0;
    for (; at < t->live_count; ++at) {
        const kg_map* other = &t->maps[t->order[at]];
        if (base + m->key_count <= other->key_base) {
            break;
        }
        base = (unsigned long long)other->key_base + other->key_count;
    }
    if (base + m->key_count > KG_KEY_SPACE) {
        return kg_fail(KG_ERROR_POOL_FULL, "the world's tile maps hold more than 2^32 - 1 cells in all");
    }
    memmove(t->order + at + 1, t->order + at, (size_t)(t->live_count - at) * sizeof *t->order);
    t->order[at] = slot;
    t->live_count += 1;
    m->key_base = (kg_u32)base;
    return KG_OK;
}

static kg_result kg_init_map(kg_map* m, const kg_tilemap_def* def)
{
    m->def = *def;
    m->def.shapes = NULL;
    m->def.tiles = NULL;
    m->key_count = (kg_u32)(def->width * def->height * def->layer_count);
    kg_result r = kg_build_templates(m, def->shapes);
    return r == KG_OK ? kg_check_tiles(m, def->tiles) : r;
}

/* Takes slot out of the live order. */
static void kg_unlist(struct kg_tilemaps* t, int slot)
{
    int at = 0;
    while (t->order[at] != slot) {
        at++;
    }
    memmove(t->order + at, t->order + at + 1, (size_t)(t->live_count - at - 1) * sizeof *t->order);
    t->live_count -= 1;
}

kg_result kg_create_tilemap(kg_world* world, const kg_tilemap_def* def, kg_tilemap* out_map)
{
    if (!world || !def || !out_map) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_create_tilemap: NULL argument");
    }
    if (kg_world_refuses(world, "kg_create_tilemap", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    kg_result r = kg_validate_tilemap_def(def);
    if (r == KG_OK && !world->tilemaps) {
        r = kg_tilemaps_create(world);
    }
    if (r != KG_OK) {
        return r;
    }
    struct kg_tilemaps* t = world->tilemaps;
    int slot = kg_take_slot(t);
    if (slot < 0) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a tile map slot");
    }
    kg_map* m = &t->maps[slot];
    kg_u32 generation = m->generation;
    memset(m, 0, sizeof *m);
    m->generation = generation;
    r = kg_init_map(m, def);
    if (r == KG_OK) {
        r = kg_assign_keys(t, slot);
        if (r == KG_OK && (r = kg_place_new_map(t)) != KG_OK) {
            kg_unlist(t, slot);
        }
    }
    if (r != KG_OK) {
        kg_map_free(m);
        return r;
    }
    kg_fill_cells(m, def->tiles);
    m->generation += 1u;
    t->layout_version += 1u;
    out_map->index = (uint32_t)slot;
    out_map->generation = m->generation;
    kg_world_wake_all(world); /* what the new map now holds up or overlaps */
    return KG_OK;
}

kg_result kg_destroy_tilemap(kg_world* world, kg_tilemap map)
{
    if (kg_world_refuses(world, "kg_destroy_tilemap", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    kg_map* m = kg_resolve_map(world, map);
    if (!m) {
        return KG_ERROR_INVALID_HANDLE;
    }
    struct kg_tilemaps* t = world->tilemaps;
    kg_unlist(t, (int)map.index);
    kg_map_free(m);
    kg_place_maps(t, t->cells, t->protos);
    m->generation += 1u;
    t->layout_version += 1u;
    kg_world_wake_all(world); /* what rested on the map */
    return KG_OK;
}

int kg_tilemap_is_valid(const kg_world* world, kg_tilemap map)
{
    struct kg_tilemaps* t = world ? world->tilemaps : NULL;
    return t && map.index < (uint32_t)t->map_count && kg_map_alive(&t->maps[map.index]) &&
           t->maps[map.index].generation == map.generation;
}

/* ---- tiles ---- */

static kg_result kg_check_cell(const kg_map* m, int layer, int x, int y)
{
    if (layer < 0 || layer >= m->def.layer_count || x < 0 || y < 0 || x >= m->def.width || y >= m->def.height) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "cell (%d, %d) of layer %d is outside the %d x %d map of %d layers",
                       x, y, layer, m->def.width, m->def.height, m->def.layer_count);
    }
    return KG_OK;
}

kg_result kg_tilemap_set_tile(kg_world* world, kg_tilemap map, int layer, int x, int y, int id)
{
    if (kg_world_refuses(world, "kg_tilemap_set_tile", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    kg_map* m = kg_resolve_map(world, map);
    if (!m) {
        return KG_ERROR_INVALID_HANDLE;
    }
    kg_result r = kg_check_cell(m, layer, x, y);
    if (r != KG_OK) {
        return r;
    }
    if (id < 0 || id >= m->def.shape_count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile id %d is not in [0, %d)", id, m->def.shape_count);
    }
    m->cells[kg_cell_index(m, layer, x, y)] = (kg_u32)id;
    m->cells_dirty = 1;
    kg_vec2 size = m->def.tile_size;
    kg_aabb cell = {{m->def.origin.x + (float)x * size.x, m->def.origin.y + (float)y * size.y},
                    {m->def.origin.x + (float)(x + 1) * size.x, m->def.origin.y + (float)(y + 1) * size.y}};
    kg_world_wake_region(world, cell); /* what rests on the tile, or is about to be inside it */
    kg_refresh_cell(m, layer, x, y);
    for (int side = 0; side < 4; ++side) {
        kg_refresh_cell(m, layer, x + kSideDx[side], y + kSideDy[side]);
    }
    return KG_OK;
}

kg_result kg_tilemap_get_tile(const kg_world* world, kg_tilemap map, int layer, int x, int y, int* out_id)
{
    const kg_map* m = kg_resolve_map(world, map);
    if (!m || !out_id) {
        return m ? kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_tilemap_get_tile: NULL out_id") : KG_ERROR_INVALID_HANDLE;
    }
    kg_result r = kg_check_cell(m, layer, x, y);
    if (r == KG_OK) {
        *out_id = (int)kg_cell_id(m->cells[kg_cell_index(m, layer, x, y)]);
    }
    return r;
}

kg_result kg_tilemap_cell_at(const kg_world* world, kg_tilemap map, kg_vec2 point, int* out_x, int* out_y)
{
    const kg_map* m = kg_resolve_map(world, map);
    if (!m || !out_x || !out_y) {
        return m ? kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_tilemap_cell_at: NULL argument") : KG_ERROR_INVALID_HANDLE;
    }
    float fx = floorf((point.x - m->def.origin.x) / m->def.tile_size.x);
    float fy = floorf((point.y - m->def.origin.y) / m->def.tile_size.y);
    if (!(fx >= 0.0f && fy >= 0.0f && fx < (float)m->def.width && fy < (float)m->def.height)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "point (%g, %g) is outside the tile map", (double)point.x,
                       (double)point.y);
    }
    *out_x = (int)fx;
    *out_y = (int)fy;
    return KG_OK;
}

kg_result kg_tilemap_get_def(const kg_world* world, kg_tilemap map, kg_tilemap_def* out)
{
    const kg_map* m = kg_resolve_map(world, map);
    if (!m || !out) {
        return m ? kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_tilemap_get_def: NULL out") : KG_ERROR_INVALID_HANDLE;
    }
    *out = m->def;
    return KG_OK;
}

void* kg_tilemap_get_user_data(const kg_world* world, kg_tilemap map)
{
    const kg_map* m = kg_resolve_map(world, map);
    return m ? m->def.user_data : NULL;
}

int kg_world_tilemap_count(const kg_world* world)
{
    return world && world->tilemaps ? world->tilemaps->live_count : 0;
}

kg_result kg_world_get_tilemaps(const kg_world* world, kg_tilemap* out, int capacity, int* count)
{
    if (!world || !count || capacity < 0 || (capacity > 0 && !out)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_get_tilemaps: bad arguments");
    }
    const struct kg_tilemaps* t = world->tilemaps;
    int n = 0;
    for (int i = 0; t && i < t->map_count && n < capacity; ++i) {
        if (kg_map_alive(&t->maps[i])) {
            out[n].index = (uint32_t)i;
            out[n].generation = t->maps[i].generation;
            n++;
        }
    }
    *count = n;
    return KG_OK;
}

kg_result kg_world_get_contact_tile(const kg_world* world, int index, kg_tilemap* out_map, int* out_layer,
                                    int* out_x, int* out_y)
{
    int count = 0;
    const kg_contact* contacts = world ? kg_collision_contacts((kg_world*)world, &count) : NULL;
    if (!contacts || index < 0 || index >= count || contacts[index].b != KG_NULL_INDEX || !world->tilemaps) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "contact %d is not a tile contact", index);
    }
    if (kg_tile_key_cell(world, contacts[index].tile, out_map, out_layer, out_x, out_y)) {
        return KG_OK;
    }
    return kg_fail(KG_ERROR_INVALID_ARGUMENT, "contact %d touches a tile map destroyed since", index);
}

int kg_tile_key_cell(const kg_world* world, kg_u32 key, kg_tilemap* out_map, int* out_layer, int* out_x, int* out_y)
{
    const struct kg_tilemaps* t = world->tilemaps;
    for (int i = 0; t && i < t->live_count; ++i) {
        const kg_map* m = &t->maps[t->order[i]];
        if (key >= m->key_base && key - m->key_base < m->key_count) {
            int offset = (int)(key - m->key_base), cells = kg_map_cell_count(m);
            if (out_map) {
                out_map->index = (uint32_t)t->order[i];
                out_map->generation = m->generation;
            }
            if (out_layer) {
                *out_layer = offset / cells;
            }
            if (out_x) {
                *out_x = offset % cells % m->def.width;
            }
            if (out_y) {
                *out_y = offset % cells / m->def.width;
            }
            return 1;
        }
    }
    return 0;
}

/* ---- collision ---- */

int kg_tilemap_collide(kg_world* world, kg_contact* out, int room, const kg_contact* previous, int previous_count)
{
    struct kg_tilemaps* t = world->tilemaps;
    if (!t || t->live_count == 0) {
        return 0;
    }
    kg_body_pool* p = &world->bodies;
    kg_tile_terrain terrain = {t->infos, t->cells, t->protos, t->live_count, world->def.speculative_distance,
                               world->def.linear_slop};
    kg_tile_bodies bodies = {p->flags,    p->aabb,     p->xf,          p->shape,          p->center,
                             p->category, p->mask,     p->generation,  p->friction,       p->restitution,
                             t->last_origin, t->last_generation, p->first_shape};
    kg_tile_bodies shapes = bodies; /* a compound body's shapes: the shape pool's, by shape slot */
    shapes.shape = world->shapes.geometry;
    shapes.category = world->shapes.category;
    shapes.mask = world->shapes.mask;
    shapes.friction = world->shapes.friction;
    shapes.restitution = world->shapes.restitution;
    kg_shape_arrays arrays = kg_world_shape_arrays(world);
    kg_tile_contacts c = {previous, 0, previous_count, out, 0u, (kg_u32)room, 0u, 0, 0};
    for (kg_u32 i = 0; i < (kg_u32)p->high_water; ++i) {
        kg_tile_collide_slot(i, &terrain, &bodies, &shapes, &arrays, &c);
        kg_tile_remember_origin(i, p->xf, p->generation, t->last_origin, t->last_generation);
    }
    kg_count_warm_starts(world, c.points, c.carried);
    return (int)c.found;
}

/* ---- for the OpenCL backend ---- */

kg_u32 kg_tilemaps_layout_version(const kg_world* world)
{
    return world->tilemaps ? world->tilemaps->layout_version : 0u;
}

int kg_tilemaps_live_count(const kg_world* world) { return world->tilemaps ? world->tilemaps->live_count : 0; }

static kg_map* kg_live_map(const kg_world* world, int live_index)
{
    return &world->tilemaps->maps[world->tilemaps->order[live_index]];
}

void kg_tilemaps_arrays(const kg_world* world, kg_tilemap_arrays* out)
{
    const struct kg_tilemaps* t = world->tilemaps;
    out->maps = t->infos;
    out->map_count = t->live_count;
    out->cells = t->cells;
    out->cell_count = t->cell_count;
    out->protos = t->protos;
    out->proto_count = t->proto_count;
}

kg_tilemap kg_tilemaps_handle(const kg_world* world, int live_index)
{
    kg_tilemap handle;
    handle.index = (uint32_t)world->tilemaps->order[live_index];
    handle.generation = kg_live_map(world, live_index)->generation;
    return handle;
}

int kg_tilemaps_take_dirty(kg_world* world, int live_index)
{
    kg_map* m = kg_live_map(world, live_index);
    int dirty = m->cells_dirty;
    m->cells_dirty = 0;
    return dirty;
}

kg_vec2* kg_tilemaps_last_origin(kg_world* world) { return world->tilemaps->last_origin; }
kg_u32* kg_tilemaps_last_generation(kg_world* world) { return world->tilemaps->last_generation; }

/* ---- snapshots (core/snapshot.c) ---- */

uint64_t kg_tilemaps_layout(uint64_t h)
{
    h = kg_snap_fold(h, sizeof(kg_tilemap_def));
    h = kg_snap_fold(h, sizeof(kg_tile_template));
    return kg_snap_fold(h, sizeof(kg_tile_proto));
}

void kg_tilemaps_snapshot(const kg_world* world, kg_snap_out* out)
{
    const struct kg_tilemaps* t = world->tilemaps;
    kg_snap_put_i32(out, t != NULL);
    if (!t) {
        return;
    }
    kg_snap_put_i32(out, t->map_count);
    kg_snap_put_i32(out, t->live_count);
    kg_snap_put_u32(out, t->layout_version);
    for (int i = 0; i < t->map_count; ++i) {
        const kg_map* m = &t->maps[i];
        kg_snap_put_u32(out, m->generation);
        if (kg_map_alive(m)) {
            kg_snap_put(out, &m->def, sizeof m->def);
            kg_snap_put_u32(out, m->key_base);
            kg_snap_put_i32(out, m->cells_dirty);
            kg_snap_put(out, m->templates, (size_t)m->def.shape_count * sizeof *m->templates);
        }
    }
    kg_snap_put(out, t->order, (size_t)t->live_count * sizeof *t->order);
    kg_snap_put_u64(out, (uint64_t)t->cell_count);
    kg_snap_put(out, t->cells, t->cell_count * sizeof *t->cells);
    size_t bodies = (size_t)world->bodies.high_water;
    kg_snap_put(out, t->last_origin, bodies * sizeof *t->last_origin);
    kg_snap_put(out, t->last_generation, bodies * sizeof *t->last_generation);
}

/* Whether a snapshot's live map can be collided with: a definition the API accepts (its
 * shapes aside) and templates of at most KG_MAX_VERTS vertices. */
static int kg_snapshot_map_sane(const kg_map* m)
{
    kg_tilemap_def d = m->def;
    kg_tile_shape empty = {0};
    d.shapes = &empty; /* the shapes are checked through their templates below */
    if (kg_validate_tilemap_def(&d) != KG_OK) {
        return 0;
    }
    for (int id = 0; id < m->def.shape_count; ++id) {
        int count = m->templates[id].proto.shape.count;
        if (count < 0 || count > KG_MAX_VERTS) {
            return 0;
        }
    }
    return 1;
}

/* Reads map slot i of a snapshot into t->maps[i] (templates allocated, cells not yet). */
static int kg_map_from_snapshot(kg_map* m, kg_snap_in* in)
{
    m->generation = kg_snap_take_u32(in, "tile maps");
    if (!kg_map_alive(m)) {
        return !in->failed;
    }
    kg_snap_take_array(in, &m->def, sizeof m->def, 1, "tile maps");
    m->def.shapes = NULL;
    m->def.tiles = NULL;
    m->key_base = kg_snap_take_u32(in, "tile maps");
    m->cells_dirty = kg_snap_take_i32(in, "tile maps");
    if (in->failed || m->def.shape_count < 1 || m->def.shape_count > KG_MAX_TILE_ID + 1 ||
        !kg_snap_has(in, sizeof *m->templates, (uint64_t)m->def.shape_count)) {
        return kg_snap_reject(in, "a tile map's definition");
    }
    m->templates = kg_alloc_zeroed((size_t)m->def.shape_count * sizeof *m->templates);
    if (!m->templates) {
        return kg_snap_reject(in, "a tile map's shapes (out of memory)");
    }
    kg_snap_take_array(in, m->templates, sizeof *m->templates, (size_t)m->def.shape_count, "tile map shapes");
    if (!in->failed && !kg_snapshot_map_sane(m)) {
        return kg_snap_reject(in, "a tile map's definition");
    }
    m->key_count = (kg_u32)(m->def.width * m->def.height * m->def.layer_count);
    return !in->failed;
}

/* Whether the live order names each live map once, in ascending key ranges. */
static int kg_order_sane(const struct kg_tilemaps* t)
{
    int live = 0;
    for (int i = 0; i < t->map_count; ++i) {
        live += kg_map_alive(&t->maps[i]);
    }
    unsigned long long next = 0;
    for (int i = 0; i < t->live_count; ++i) {
        int slot = t->order[i];
        if (slot < 0 || slot >= t->map_count || !kg_map_alive(&t->maps[slot]) || t->maps[slot].key_base < next) {
            return 0;
        }
        next = (unsigned long long)t->maps[slot].key_base + t->maps[slot].key_count;
    }
    return live == t->live_count && next <= KG_KEY_SPACE;
}

/* Whether every cell names a tile id of its map. */
static int kg_cells_sane(const struct kg_tilemaps* t)
{
    for (int i = 0; i < t->live_count; ++i) {
        const kg_map* m = &t->maps[t->order[i]];
        for (kg_u32 k = 0; k < m->key_count; ++k) {
            if (kg_cell_id(m->cells[k]) >= (kg_u32)m->def.shape_count) {
                return 0;
            }
        }
    }
    return 1;
}

/* The live maps laid out (kg_place_maps) and their cells read. */
static int kg_cells_from_snapshot(struct kg_tilemaps* t, kg_snap_in* in)
{
    size_t cells = 0, protos = 0;
    for (int i = 0; i < t->live_count; ++i) {
        cells += t->maps[t->order[i]].key_count;
        protos += (size_t)t->maps[t->order[i]].def.shape_count;
    }
    uint64_t snap_cells = kg_snap_take_u64(in, "tile cells");
    if (in->failed || snap_cells != (uint64_t)cells || !kg_snap_has(in, sizeof(kg_u32), snap_cells)) {
        return kg_snap_reject(in, "tile cells");
    }
    kg_u32* cell_array = kg_alloc_zeroed((cells > 0 ? cells : 1) * sizeof *cell_array);
    kg_tile_proto* proto_array = kg_alloc_zeroed((protos > 0 ? protos : 1) * sizeof *proto_array);
    if (!cell_array || !proto_array) {
        kg_free(cell_array);
        kg_free(proto_array);
        return kg_snap_reject(in, "tile cells (out of memory)");
    }
    kg_place_maps(t, cell_array, proto_array);
    kg_snap_take_array(in, t->cells, sizeof *t->cells, cells, "tile cells");
    return !in->failed && (kg_cells_sane(t) || kg_snap_reject(in, "a tile cell's id"));
}

static void kg_tilemaps_free(struct kg_tilemaps* t)
{
    kg_world none;
    memset(&none, 0, sizeof none);
    none.tilemaps = t;
    kg_tilemaps_destroy(&none);
}

/* The arrays of a snapshot's maps, map_count slots, live of them live, read. */
static int kg_tilemaps_arrays_from_snapshot(struct kg_tilemaps* t, int bodies, int high_water, kg_snap_in* in)
{
    int n = t->map_count > 0 ? t->map_count : 1;
    t->maps = kg_alloc_zeroed((size_t)n * sizeof *t->maps);
    t->order = kg_alloc_zeroed((size_t)n * sizeof *t->order);
    t->infos = kg_alloc_zeroed((size_t)n * sizeof *t->infos);
    t->last_origin = kg_alloc_zeroed((size_t)bodies * sizeof *t->last_origin);
    t->last_generation = kg_alloc_zeroed((size_t)bodies * sizeof *t->last_generation);
    if (!t->maps || !t->order || !t->infos || !t->last_origin || !t->last_generation) {
        return kg_snap_reject(in, "tile maps (out of memory)");
    }
    t->map_capacity = n;
    for (int i = 0; i < t->map_count && kg_map_from_snapshot(&t->maps[i], in); ++i) {
    }
    kg_snap_take_array(in, t->order, sizeof *t->order, (size_t)t->live_count, "tile map order");
    if (in->failed || !kg_order_sane(t)) {
        return kg_snap_reject(in, "tile map order");
    }
    if (!kg_cells_from_snapshot(t, in)) {
        return 0;
    }
    kg_snap_take_array(in, t->last_origin, sizeof *t->last_origin, (size_t)high_water, "one-way platform state");
    kg_snap_take_array(in, t->last_generation, sizeof *t->last_generation, (size_t)high_water,
                       "one-way platform state");
    return !in->failed;
}

kg_result kg_tilemaps_from_snapshot(const kg_world* world, int high_water, kg_snap_in* in, struct kg_tilemaps** out)
{
    *out = NULL;
    int present = kg_snap_take_i32(in, "tile maps");
    if (in->failed || !present) {
        return in->failed ? KG_ERROR_INVALID_ARGUMENT : KG_OK;
    }
    struct kg_tilemaps* t = kg_alloc_zeroed(sizeof *t);
    if (!t) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the tile maps");
    }
    t->map_count = kg_snap_take_i32(in, "tile maps");
    t->live_count = kg_snap_take_i32(in, "tile maps");
    t->layout_version = kg_snap_take_u32(in, "tile maps");
    if (!in->failed && (t->map_count < 0 || t->map_count > (1 << 20) || t->live_count < 0 ||
                        t->live_count > t->map_count || !kg_snap_has(in, sizeof(kg_u32), (uint64_t)t->map_count))) {
        kg_snap_reject(in, "tile map counts");
    }
    if (in->failed || !kg_tilemaps_arrays_from_snapshot(t, world->def.max_bodies, high_water, in)) {
        t->map_count = t->map_count < 0 || !t->maps ? 0 : t->map_count;
        kg_tilemaps_free(t);
        return KG_ERROR_INVALID_ARGUMENT;
    }
    *out = t;
    return KG_OK;
}

void kg_tilemaps_adopt(kg_world* world, struct kg_tilemaps* staged)
{
    kg_tilemaps_destroy(world);
    world->tilemaps = staged;
}

void kg_tilemaps_discard(struct kg_tilemaps* staged)
{
    if (staged) {
        kg_tilemaps_free(staged);
    }
}

kg_result kg_tilemap_get_shape(const kg_world* world, kg_tilemap map, int id, kg_tile_shape* out)
{
    const kg_map* m = kg_resolve_map(world, map);
    if (!m) {
        return KG_ERROR_INVALID_HANDLE;
    }
    if (id < 0 || id >= m->def.shape_count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile id %d: the map has %d shapes", id, m->def.shape_count);
    }
    const kg_tile_template* t = &m->templates[id];
    const kg_shape* s = &t->proto.shape;
    memset(out, 0, sizeof *out);
    if (s->count == 1) {
        out->type = KG_TILE_SHAPE_CIRCLE;
        out->center = kg_scale(1.0f / m->def.tile_size.x, s->vertices[0]);
        out->radius = s->radius / m->def.tile_size.x;
    } else if (s->count >= 3) {
        out->type = KG_TILE_SHAPE_POLYGON;
        out->count = s->count;
        memcpy(out->vertices, t->unit, (size_t)s->count * sizeof *out->vertices);
        out->one_way = (t->proto.flags & KG_TILE_FLAG_ONE_WAY) != 0u;
    }
    return KG_OK;
}

#include "core/shape_pool.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/generation.h"
#include "core/snapshot_io.h"

#include <string.h>

#define KG_SHAPE_POOL_ARRAYS(X)                                                                           \
    X(body) X(next) X(density) X(friction) X(restitution) X(category) X(mask) X(flags) \
    X(generation) X(user_data)

kg_result kg_shape_pool_init(kg_shape_pool* pool, int capacity)
{
    memset(pool, 0, sizeof *pool);
    pool->capacity = capacity;
#define KG_ALLOC_ARRAY(name)                                                                          \
    pool->name = kg_alloc_zeroed((size_t)capacity * sizeof *pool->name);                              \
    if (!pool->name) {                                                                                \
        kg_shape_pool_free(pool);                                                                     \
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a pool of %d shapes", capacity);      \
    }
    KG_SHAPE_POOL_ARRAYS(KG_ALLOC_ARRAY)
#undef KG_ALLOC_ARRAY
    return KG_OK;
}

void kg_shape_pool_free(kg_shape_pool* pool)
{
    kg_free(pool->geometry);
    pool->geometry = NULL;
#define KG_FREE_ARRAY(name) kg_free(pool->name); pool->name = NULL;
    KG_SHAPE_POOL_ARRAYS(KG_FREE_ARRAY)
#undef KG_FREE_ARRAY
}

/* The pool with room for capacity shapes, its contents kept; unchanged on failure. */
static kg_result kg_shape_pool_grow(kg_shape_pool* pool, int capacity)
{
    kg_shape_pool grown;
    KG_TRY(kg_shape_pool_init(&grown, capacity));
#define KG_COPY_ARRAY(name) memcpy(grown.name, pool->name, (size_t)pool->capacity * sizeof *pool->name);
    KG_SHAPE_POOL_ARRAYS(KG_COPY_ARRAY)
#undef KG_COPY_ARRAY
    grown.tag = pool->tag;
    kg_generation_seed(grown.generation, pool->capacity, capacity, pool->tag);
    if (pool->geometry) {
        grown.geometry = kg_alloc_zeroed((size_t)capacity * sizeof *grown.geometry);
        if (!grown.geometry) {
            kg_shape_pool_free(&grown);
            return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a pool of %d shapes", capacity);
        }
        memcpy(grown.geometry, pool->geometry, (size_t)pool->capacity * sizeof *pool->geometry);
    }
    grown.high_water = pool->high_water;
    grown.count = pool->count;
    grown.first_free = pool->first_free;
    grown.held = pool->held;
    grown.version = pool->version;
    grown.compound_bodies = pool->compound_bodies;
    kg_shape_pool_free(pool);
    *pool = grown;
    return KG_OK;
}

kg_result kg_shape_pool_reserve(kg_shape_pool* pool, int more)
{
    int64_t need = (int64_t)pool->count + pool->held + more;
    if (need <= pool->capacity) {
        return KG_OK;
    }
    int64_t want = need + need / 2;
    if (want > (1 << 28) || kg_shape_pool_grow(pool, (int)want) != KG_OK) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot grow the shape pool to %lld shapes", (long long)need);
    }
    return KG_OK;
}

kg_result kg_shape_pool_reserve_geometry(kg_shape_pool* pool)
{
    if (!pool->geometry) {
        pool->geometry = kg_alloc_zeroed((size_t)pool->capacity * sizeof *pool->geometry);
    }
    return pool->geometry ? KG_OK
                          : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the geometry of %d shapes", pool->capacity);
}

int kg_shape_pool_acquire(kg_shape_pool* pool)
{
    for (int i = pool->first_free; i < pool->high_water; ++i) {
        if (pool->flags[i] == 0u) {
            pool->first_free = i + 1;
            pool->count += 1;
            return i;
        }
    }
    if (pool->high_water == pool->capacity) {
        int64_t want = (int64_t)pool->capacity + pool->capacity / 2 + 1;
        if (want > (1 << 28) || kg_shape_pool_grow(pool, (int)want) != KG_OK) {
            kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot grow the shape pool past %d shapes", pool->capacity);
            return -1;
        }
    }
    pool->first_free = pool->high_water + 1;
    pool->count += 1;
    return pool->high_water++;
}

void kg_shape_pool_release(kg_shape_pool* pool, int index)
{
    pool->flags[index] = KG_SHAPE_HELD;
    pool->generation[index] = kg_generation_next(pool->generation[index]);
    if (pool->generation[index] == 0) {
        pool->generation[index] = 1;
    }
    pool->count -= 1;
    pool->held += 1;
    pool->version += 1u;
}

void kg_shape_pool_free_held(kg_shape_pool* pool)
{
    for (int i = 0; pool->held > 0 && i < pool->high_water; ++i) {
        if (pool->flags[i] == KG_SHAPE_HELD) {
            pool->flags[i] = 0u;
            pool->held -= 1;
            pool->first_free = i < pool->first_free ? i : pool->first_free;
        }
    }
    while (pool->high_water > 0 && pool->flags[pool->high_water - 1] == 0u) {
        pool->high_water -= 1;
    }
}

int kg_shape_pool_resolve(const kg_shape_pool* pool, kg_shape_id handle)
{
    int i = (int)handle.index;
    if (handle.generation == 0 || handle.index >= (uint32_t)pool->high_water || !kg_shape_alive(pool, i) ||
        pool->generation[i] != handle.generation) {
        kg_fail(KG_ERROR_INVALID_HANDLE, "shape handle {%u, %u} is stale, foreign or invalid (no live shape of this world has it)",
                handle.index, handle.generation);
        return -1;
    }
    return i;
}

void kg_shape_list_insert(kg_shape_pool* pool, kg_u32* first, kg_u32 slot)
{
    kg_u32* link = first;
    while (*link != KG_NULL_INDEX && *link < slot) {
        link = &pool->next[*link];
    }
    pool->next[slot] = *link;
    *link = slot;
}

void kg_shape_list_remove(kg_shape_pool* pool, kg_u32* first, kg_u32 slot)
{
    kg_u32* link = first;
    while (*link != slot) {
        link = &pool->next[*link];
    }
    *link = pool->next[slot];
}

/* ---- snapshots (core/snapshot.c) ---- */

uint64_t kg_shape_pool_layout(uint64_t h)
{
    const kg_shape_pool* none = NULL;
#define KG_FOLD_SIZE(name) h = kg_snap_fold(h, sizeof *none->name);
    KG_SHAPE_POOL_ARRAYS(KG_FOLD_SIZE)
#undef KG_FOLD_SIZE
    return kg_snap_fold(h, sizeof *none->geometry);
}

void kg_shape_pool_snapshot(const kg_shape_pool* pool, kg_snap_out* out)
{
    int counts[] = {pool->capacity, pool->high_water, pool->count, pool->first_free, pool->held,
                    pool->compound_bodies, pool->geometry != NULL};
    kg_snap_put(out, counts, sizeof counts);
    kg_snap_put_u32(out, pool->tag);
    kg_snap_put_u32(out, pool->version);
    size_t n = (size_t)pool->high_water;
#define KG_PUT_ARRAY(name) kg_snap_put(out, pool->name, n * sizeof *pool->name);
    KG_SHAPE_POOL_ARRAYS(KG_PUT_ARRAY)
#undef KG_PUT_ARRAY
    kg_snap_put(out, pool->generation + n, (size_t)(pool->capacity - pool->high_water) * sizeof *pool->generation);
    if (pool->geometry) {
        kg_snap_put(out, pool->geometry, n * sizeof *pool->geometry);
    }
}

/* Whether the counts of a snapshot's pool fit together (they size what is read). */
static int kg_shape_counts_sane(const int* c)
{
    int capacity = c[0], high_water = c[1], count = c[2], first_free = c[3], held = c[4];
    return capacity > 0 && capacity <= (1 << 28) && high_water >= 0 && high_water <= capacity && count >= 0 &&
           held >= 0 && (int64_t)count + held <= high_water && first_free >= 0 && first_free <= high_water + 1 &&
           c[5] >= 0;
}

/* Whether the shape lists and flags of pool can be walked safely (bodies: their pool's capacity). */
static int kg_shape_links_sane(const kg_shape_pool* pool, int bodies)
{
    int alive = 0, held = 0;
    for (int i = 0; i < pool->high_water; ++i) {
        kg_u32 f = pool->flags[i];
        alive += (f & KG_SHAPE_ALIVE) != 0u;
        held += f == KG_SHAPE_HELD;
        kg_u32 next = pool->next[i];
        int next_bad = next != KG_NULL_INDEX && (next <= (kg_u32)i || next >= (kg_u32)pool->high_water);
        if ((f & KG_SHAPE_ALIVE) && ((int64_t)pool->body[i] >= bodies || next_bad)) {
            return 0;
        }
    }
    return alive == pool->count && held == pool->held;
}

kg_result kg_shape_pool_from_snapshot(kg_shape_pool* pool, int bodies, kg_snap_in* in)
{
    int c[7] = {0};
    kg_snap_take_array(in, c, sizeof c[0], 7, "shape pool");
    kg_u32 tag = kg_snap_take_u32(in, "shape pool");
    kg_u32 version = kg_snap_take_u32(in, "shape pool");
    if (!in->failed && (!kg_shape_counts_sane(c) || !kg_snap_has(in, sizeof *pool->generation, (uint64_t)c[0]))) {
        kg_snap_reject(in, "shape pool counts"); /* every slot's generation is written */
    }
    if (in->failed) {
        return KG_ERROR_INVALID_ARGUMENT;
    }
    KG_TRY(kg_shape_pool_init(pool, c[0]));
    pool->high_water = c[1];
    pool->count = c[2];
    pool->first_free = c[3];
    pool->held = c[4];
    pool->compound_bodies = c[5];
    pool->tag = tag;
    pool->version = version;
    size_t n = (size_t)pool->high_water;
#define KG_TAKE_ARRAY(name) kg_snap_take_array(in, pool->name, sizeof *pool->name, n, "shape pool arrays");
    KG_SHAPE_POOL_ARRAYS(KG_TAKE_ARRAY)
#undef KG_TAKE_ARRAY
    kg_snap_take_array(in, pool->generation + n, sizeof *pool->generation, (size_t)(pool->capacity - pool->high_water),
                       "shape pool generations");
    if (c[6] && !in->failed && kg_shape_pool_reserve_geometry(pool) != KG_OK) {
        kg_shape_pool_free(pool);
        return KG_ERROR_OUT_OF_MEMORY;
    }
    if (c[6]) {
        kg_snap_take_array(in, pool->geometry, sizeof *pool->geometry, n, "shape geometry");
    }
    if (!in->failed && !kg_shape_links_sane(pool, bodies)) {
        kg_snap_reject(in, "shape lists");
    }
    if (in->failed) {
        kg_shape_pool_free(pool);
        return KG_ERROR_INVALID_ARGUMENT;
    }
    return KG_OK;
}

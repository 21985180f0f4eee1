#include "core/shape_pool.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/generation.h"

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

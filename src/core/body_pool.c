#include "core/body_pool.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/generation.h"
#include "collide/shape.h"

#include <string.h>

#define KG_POOL_ARRAYS(X)                                                                          \
    X(center) X(rot) X(velocity) X(omega) X(force) X(torque) X(drag) X(sleep_time) X(island) X(xf) X(aabb) X(shape) X(first_shape) X(shape_count) X(local_center) \
    X(mass) X(inertia) X(inv_mass) X(inv_inertia) X(friction) X(restitution) X(linear_damping)      \
    X(angular_damping) X(category) X(mask) X(flags) X(generation) X(user_data)

kg_result kg_body_pool_init(kg_body_pool* pool, int capacity)
{
    memset(pool, 0, sizeof *pool);
    pool->capacity = capacity;
#define KG_ALLOC_ARRAY(name)                                                              \
    pool->name = kg_alloc_zeroed((size_t)capacity * sizeof *pool->name);                  \
    if (!pool->name) {                                                                    \
        kg_body_pool_free(pool);                                                          \
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a pool of %d bodies", capacity); \
    }
    KG_POOL_ARRAYS(KG_ALLOC_ARRAY)
#undef KG_ALLOC_ARRAY
    return KG_OK;
}

void kg_body_pool_free(kg_body_pool* pool)
{
#define KG_FREE_ARRAY(name) kg_free(pool->name); pool->name = NULL;
    KG_POOL_ARRAYS(KG_FREE_ARRAY)
#undef KG_FREE_ARRAY
}

int kg_body_pool_acquire(kg_body_pool* pool)
{
    for (int i = pool->first_free; i < pool->high_water; ++i) {
        if (!kg_pool_alive(pool, i)) {
            pool->first_free = i + 1;
            pool->count += 1;
            return i;
        }
    }
    pool->first_free = pool->high_water + 1;
    if (pool->high_water == pool->capacity) {
        return -1;
    }
    pool->count += 1;
    return pool->high_water++;
}

void kg_body_pool_release(kg_body_pool* pool, int index)
{
    pool->flags[index] = 0;
    pool->generation[index] = kg_generation_next(pool->generation[index]);
    pool->count -= 1;
    if (index < pool->first_free) {
        pool->first_free = index;
    }
    while (pool->high_water > 0 && !kg_pool_alive(pool, pool->high_water - 1)) {
        pool->high_water -= 1;
    }
}

int kg_body_pool_resolve(const kg_body_pool* pool, kg_body handle)
{
    int i = (int)handle.index;
    if (handle.generation == 0 || handle.index >= (uint32_t)pool->capacity || !kg_pool_alive(pool, i) ||
        pool->generation[i] != handle.generation) {
        kg_fail(KG_ERROR_INVALID_HANDLE, "body handle {%u, %u} is stale, foreign or invalid (no live body of this world has it)",
                handle.index, handle.generation);
        return -1;
    }
    return i;
}

void kg_body_update_transform(kg_body_pool* pool, int i)
{
    kg_xf xf;
    xf.q = pool->rot[i];
    xf.p = kg_sub(pool->center[i], kg_rotate(xf.q, pool->local_center[i]));
    pool->xf[i] = xf;
    pool->aabb[i] = kg_shape_aabb(&pool->shape[i], xf);
}

/* Slot generations carry their world: the high bits of every generation a world hands
 * out hold the world's tag, the low bits count the slot's reuses. A handle from another
 * world then matches no live slot here, and is refused as KG_ERROR_INVALID_HANDLE like a
 * stale one (include/kgyro/types.h). The tag is never 0, so no tagged generation is 0
 * and the all-zero handle stays invalid. Tags come from a global counter (not from
 * randomness or addresses), so runs stay reproducible; they cycle after 255 worlds. */
#ifndef KG_GENERATION_H
#define KG_GENERATION_H

#include "core/kg_shared.h"

#define KG_GENERATION_TAG_SHIFT 24
#define KG_GENERATION_COUNT_MASK ((1u << KG_GENERATION_TAG_SHIFT) - 1u)

/* The next world's tag, in [1, 255]; safe from any thread. */
kg_u32 kg_next_world_tag(void);

/* The generation a never used slot of a world with this tag starts at. */
static inline kg_u32 kg_generation_first(kg_u32 tag) { return tag << KG_GENERATION_TAG_SHIFT; }

/* The generation after g: the count moves on, the tag stays. */
static inline kg_u32 kg_generation_next(kg_u32 g)
{
    return (g & ~KG_GENERATION_COUNT_MASK) | ((g + 1u) & KG_GENERATION_COUNT_MASK);
}

/* Sets generation[from..to) to the first generation of tag. */
static inline void kg_generation_seed(kg_u32* generation, int from, int to, kg_u32 tag)
{
    for (int i = from; i < to; ++i) {
        generation[i] = kg_generation_first(tag);
    }
}

#endif

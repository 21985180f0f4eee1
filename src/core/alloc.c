#include "core/alloc.h"

#include <stdlib.h>
#include <string.h>

#define KG_ALIGNMENT 64

void* kg_alloc_zeroed(size_t size)
{
    size_t rounded = (size + KG_ALIGNMENT - 1) / KG_ALIGNMENT * KG_ALIGNMENT;
    if (rounded == 0) {
        rounded = KG_ALIGNMENT;
    }
    void* p = aligned_alloc(KG_ALIGNMENT, rounded);
    if (p) {
        memset(p, 0, rounded);
    }
    return p;
}

void kg_free(void* p) { free(p); }

char* kg_copy_text(const char* text)
{
    size_t n = strlen(text) + 1;
    char* copy = kg_alloc_zeroed(n);
    if (copy) {
        memcpy(copy, text, n);
    }
    return copy;
}

/* All engine memory goes through here: 64-byte aligned (a cache line: SIMD rows of any
 * width, device buffers),
 * zeroed, and only ever called outside a step. */
#ifndef KG_ALLOC_H
#define KG_ALLOC_H

#include <stddef.h>

void* kg_alloc_zeroed(size_t size);
void kg_free(void* p);
/* A copy of text in engine memory (kg_free it), or NULL when out of memory. */
char* kg_copy_text(const char* text);

#endif

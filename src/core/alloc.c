/* madvise(MADV_HUGEPAGE) is a Linux extension, outside POSIX */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE
#endif
#include "core/alloc.h"

#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#define KG_ALIGNMENT 64
/* Pools this large (a contact list, the solver's rows) go on 2 MiB pages where the
 * system allows it: the step streams them and gathers bodies across them, and with 4 KiB
 * pages that is a page walk every 4 KiB. */
#define KG_HUGE_POOL ((size_t)4 << 20)
#define KG_HUGE_PAGE ((size_t)2 << 20)

static void kg_advise_huge(void* p, size_t size)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (size >= KG_HUGE_POOL) {
        (void)madvise(p, size, MADV_HUGEPAGE);
    }
#else
    (void)p;
    (void)size;
#endif
}

void* kg_alloc_zeroed(size_t size)
{
    size_t alignment = size >= KG_HUGE_POOL ? KG_HUGE_PAGE : KG_ALIGNMENT;
    size_t rounded = (size + alignment - 1) / alignment * alignment;
    if (rounded == 0) {
        rounded = KG_ALIGNMENT;
    }
    void* p = aligned_alloc(alignment, rounded);
    if (p) {
        kg_advise_huge(p, rounded);
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

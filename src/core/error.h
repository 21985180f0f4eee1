/* Error reporting: set a message and return the code, in one expression. */
#ifndef KG_ERROR_H
#define KG_ERROR_H

#include "kgyro/types.h"

#if defined(__GNUC__)
#define KG_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define KG_PRINTF(a, b)
#endif

kg_result kg_fail(kg_result code, const char* fmt, ...) KG_PRINTF(2, 3);
void kg_clear_error(void);
/* The code passed to the last kg_fail on this thread. */
kg_result kg_last_result(void);
/* Prints a warning to stderr once per distinct key for the whole process. */
void kg_warn_once(const char* key, const char* fmt, ...) KG_PRINTF(2, 3);

/* Returns the result of expr from the calling function unless it is KG_OK. */
#define KG_TRY(expr)                \
    do {                            \
        kg_result kg_try_ = (expr); \
        if (kg_try_ != KG_OK) {     \
            return kg_try_;         \
        }                           \
    } while (0)

#endif

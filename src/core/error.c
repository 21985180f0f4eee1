#include "core/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static _Thread_local char g_last_error[512];
static _Thread_local kg_result g_last_result;

const char* kg_result_string(kg_result result)
{
    switch (result) {
    case KG_OK: return "ok";
    case KG_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case KG_ERROR_INVALID_HANDLE: return "invalid handle";
    case KG_ERROR_POOL_FULL: return "pool full";
    case KG_ERROR_OUT_OF_MEMORY: return "out of memory";
    case KG_ERROR_DEGENERATE_SHAPE: return "degenerate shape";
    case KG_ERROR_IO: return "i/o error";
    case KG_ERROR_PARSE: return "parse error";
    case KG_ERROR_BACKEND: return "backend error";
    case KG_ERROR_UNSUPPORTED: return "unsupported";
    case KG_ERROR_LOCKED: return "world locked inside a step";
    case KG_ERROR_NOT_FOUND: return "not found";
    }
    return "unknown error";
}

const char* kg_last_error(void) { return g_last_error; }

void kg_clear_error(void)
{
    g_last_error[0] = '\0';
    g_last_result = KG_OK;
}

kg_result kg_last_result(void) { return g_last_result; }

kg_result kg_fail(kg_result code, const char* fmt, ...)
{
    g_last_result = code;
    va_list args;
    va_start(args, fmt);
    vsnprintf(g_last_error, sizeof g_last_error, fmt, args);
    va_end(args);
    return code;
}

void kg_warn_once(const char* key, const char* fmt, ...)
{
    static char seen[16][64];
    static int seen_count;
    for (int i = 0; i < seen_count; ++i) {
        if (strncmp(seen[i], key, sizeof seen[i] - 1) == 0) {
            return;
        }
    }
    if (seen_count < 16) {
        snprintf(seen[seen_count++], sizeof seen[0], "%s", key);
    }
    va_list args;
    va_start(args, fmt);
    fputs("kgyro: warning: ", stderr);
    vfprintf(stderr, fmt, args);
    fputc('\n', stderr);
    va_end(args);
}

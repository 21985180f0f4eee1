/* Shared by the fuzz targets: reading typed values from the fuzzer's bytes, and the
 * check that turns a broken engine contract into a crash libFuzzer records.
 *
 * A target is one fuzz/fuzz_NAME.c defining LLVMFuzzerTestOneInput. scripts/fuzz.sh
 * links it with libFuzzer; tests/cases/fuzz_regress.cmake links it with
 * fuzz/replay_main.c into an ordinary program that replays tests/regress/NAME and
 * fuzz/corpus/NAME as a ctest. */
#ifndef KG_FUZZ_COMMON_H
#define KG_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

/* A broken contract must abort even in a release build, so no assert(). */
#define FUZZ_REQUIRE(cond, what)                                                     \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: contract broken: %s (%s)\n", __FILE__, __LINE__, \
                    what, #cond);                                                    \
            abort();                                                                 \
        }                                                                            \
    } while (0)

/* The fuzzer's bytes, consumed front to back; reading past the end gives zeros so
 * that every input, however short, is a complete test case. */
typedef struct fuzz_reader {
    const uint8_t* data;
    size_t size;
    size_t at;
} fuzz_reader;

static inline fuzz_reader fuzz_reader_make(const uint8_t* data, size_t size)
{
    fuzz_reader r = {data, size, 0};
    return r;
}

static inline uint8_t fuzz_take_u8(fuzz_reader* r)
{
    return r->at < r->size ? r->data[r->at++] : 0;
}

/* Raw IEEE bits, so NaN, infinities, denormals and 1e38 all come out of the fuzzer. */
static inline float fuzz_take_float(fuzz_reader* r)
{
    uint8_t bytes[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) {
        bytes[i] = fuzz_take_u8(r);
    }
    float value;
    memcpy(&value, bytes, sizeof value);
    return value;
}

#endif

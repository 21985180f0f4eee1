/* Tiled tile layer data in base64: uncompressed, zlib or gzip (docs/tilemaps.md). */
#ifndef KG_TILED_DECODE_H
#define KG_TILED_DECODE_H

#include <stddef.h>

/* Decodes text (standard base64) and inflates it as compression says ("" none, "zlib",
 * "gzip") into exactly size bytes at out. NULL when that worked, else what is wrong (a
 * static message, such as "is not base64", completed by the caller with the JSON path).
 * The decompressed data must be size bytes exactly: more (a bomb), fewer, a truncated or
 * corrupt stream are refused, and nothing beyond out and the decoded input is allocated. */
const char* kg_tiled_decode(const char* text, const char* compression, unsigned char* out, size_t size);

#endif

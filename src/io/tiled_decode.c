/* Tiled tile layer data: base64, then zlib or gzip inflated through zlib (a Debian
 * package, zlib1g-dev), under a hard cap: the output buffer is exactly the layer's
 * width x height x 4 bytes, and a stream that would write one byte more is refused. */
#include "io/tiled_decode.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static int kg_base64_digit(char c)
{
    if (c >= 'A' && c <= 'Z') {
        return c - 'A';
    }
    if (c >= 'a' && c <= 'z') {
        return c - 'a' + 26;
    }
    if (c >= '0' && c <= '9') {
        return c - '0' + 52;
    }
    return c == '+' ? 62 : (c == '/' ? 63 : -1);
}

/* Decodes standard base64 (padding optional) into out, at most capacity bytes; the count
 * in *written. 0 when malformed or longer than capacity. */
static int kg_base64_decode(const char* text, unsigned char* out, size_t capacity, size_t* written)
{
    size_t length = strlen(text);
    while (length > 0 && text[length - 1] == '=') {
        length--;
    }
    uint32_t bits = 0;
    int held = 0;
    *written = 0;
    for (size_t i = 0; i < length; ++i) {
        int digit = kg_base64_digit(text[i]);
        if (digit < 0) {
            return 0;
        }
        bits = (bits << 6) | (uint32_t)digit;
        held += 6;
        if (held >= 8) {
            held -= 8;
            if (*written == capacity) {
                return 0;
            }
            out[(*written)++] = (unsigned char)(bits >> held);
        }
    }
    return 1;
}

/* Whether the stream z, which filled its output, still has output to give: a bomb, as
 * opposed to a stream cut off right after its last byte of data. */
static int kg_inflate_has_more(z_stream* z)
{
    unsigned char extra;
    z->next_out = &extra;
    z->avail_out = 1;
    int status = inflate(z, Z_FINISH);
    return z->avail_out == 0 || status == Z_STREAM_END;
}

/* Inflates in (zlib, or gzip when gzip) into exactly size bytes at out. */
static const char* kg_inflate_exact(const unsigned char* in, size_t in_size, int gzip, unsigned char* out,
                                    size_t size)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, gzip ? 15 + 16 : 15) != Z_OK) {
        return "cannot start zlib (out of memory)";
    }
    z.next_in = (unsigned char*)in;
    z.avail_in = (uInt)in_size;
    z.next_out = out;
    z.avail_out = (uInt)size;
    int status = inflate(&z, Z_FINISH);
    const char* what = NULL;
    if (status == Z_STREAM_END) {
        what = z.total_out != size ? "decompresses to fewer bytes than the layer needs"
               : z.avail_in != 0   ? "has bytes after the end of the compressed stream"
                                   : NULL;
    } else if (status == Z_BUF_ERROR && z.avail_out == 0 && kg_inflate_has_more(&z)) {
        what = "decompresses to more bytes than the layer needs";
    } else if (status == Z_BUF_ERROR) {
        what = "is truncated (the compressed stream ends early)";
    } else if (status == Z_MEM_ERROR) {
        what = "cannot be decompressed (out of memory)";
    } else {
        what = "is not valid compressed data";
    }
    inflateEnd(&z);
    return what;
}

const char* kg_tiled_decode(const char* text, const char* compression, unsigned char* out, size_t size)
{
    size_t written = 0;
    if (compression[0] == '\0') {
        int ok = kg_base64_decode(text, out, size, &written);
        return !ok ? "is not base64 of the layer's size" : written != size ? "is base64 of too few bytes" : NULL;
    }
    int gzip = strcmp(compression, "gzip") == 0;
    size_t capacity = strlen(text) / 4 * 3 + 3;
    if (capacity > (size_t)UINT32_MAX) {
        return "is too long";
    }
    unsigned char* packed = malloc(capacity);
    if (!packed) {
        return "cannot be decoded (out of memory)";
    }
    const char* what = kg_base64_decode(text, packed, capacity, &written) ? NULL : "is not base64";
    if (!what) {
        what = kg_inflate_exact(packed, written, gzip, out, size);
    }
    free(packed);
    return what;
}

#include "gif.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KG_LZW_MAX_CODE 4095
#define KG_LZW_TABLE_SIZE 8192 /* a power of two, twice the codes, so probes stay short */
#define KG_LZW_CLEAR 256
#define KG_LZW_END 257
#define KG_GIF_UNCHANGED 255 /* transparent: the pixel of the frame before shows through */

typedef struct kg_lzw_writer {
    FILE* file;
    uint32_t bits; /* pending bits, least significant first */
    int bit_count;
    uint8_t block[255];
    int block_length;
    int code_size;
    int next_code;
} kg_lzw_writer;

struct kg_gif {
    FILE* file;
    int width, height;
    uint8_t* previous; /* the last frame, to find what changed */
    int frame_count;
    int failed;
    int32_t keys[KG_LZW_TABLE_SIZE]; /* (prefix << 8 | byte) + 1, 0 = free */
    int16_t codes[KG_LZW_TABLE_SIZE];
};

static void kg_put16(FILE* file, int value)
{
    fputc(value & 0xff, file);
    fputc((value >> 8) & 0xff, file);
}

kg_gif* kg_gif_open(const char* path, int width, int height, const uint8_t* palette)
{
    kg_gif* gif = calloc(1, sizeof *gif);
    if (!gif || width < 1 || height < 1 || width > 65535 || height > 65535) {
        free(gif);
        return NULL;
    }
    gif->width = width;
    gif->height = height;
    gif->previous = malloc((size_t)width * (size_t)height);
    gif->file = gif->previous ? fopen(path, "wb") : NULL;
    if (!gif->file) {
        free(gif->previous);
        free(gif);
        return NULL;
    }
    fwrite("GIF89a", 1, 6, gif->file);
    kg_put16(gif->file, width);
    kg_put16(gif->file, height);
    fputc(0xf7, gif->file); /* global colour table of 2^(7+1) entries, 8 bits per primary */
    fputc(0, gif->file);    /* background colour index */
    fputc(0, gif->file);    /* square pixels */
    fwrite(palette, 1, 256 * 3, gif->file);
    static const uint8_t kLoopForever[19] = {0x21, 0xff, 11,  'N', 'E', 'T', 'S', 'C', 'A', 'P',
                                             'E',  '2',  '.', '0', 3,   1,   0,   0,   0};
    fwrite(kLoopForever, 1, sizeof kLoopForever, gif->file);
    return gif;
}

static void kg_lzw_flush_block(kg_lzw_writer* w)
{
    if (w->block_length > 0) {
        fputc(w->block_length, w->file);
        fwrite(w->block, 1, (size_t)w->block_length, w->file);
        w->block_length = 0;
    }
}

static void kg_lzw_put(kg_lzw_writer* w, int code, int size)
{
    w->bits |= (uint32_t)code << w->bit_count;
    w->bit_count += size;
    while (w->bit_count >= 8) {
        w->block[w->block_length++] = (uint8_t)(w->bits & 0xff);
        w->bits >>= 8;
        w->bit_count -= 8;
        if (w->block_length == 255) {
            kg_lzw_flush_block(w);
        }
    }
}

static void kg_lzw_restart(kg_gif* gif, kg_lzw_writer* w)
{
    memset(gif->keys, 0, sizeof gif->keys);
    w->code_size = 9;
    w->next_code = KG_LZW_END + 1;
}

/* The code of string (prefix, byte), or -1 with *slot where it would go. */
static int kg_lzw_find(const kg_gif* gif, int prefix, int byte, int* slot)
{
    int32_t key = ((int32_t)prefix << 8 | byte) + 1;
    uint32_t at = ((uint32_t)key * 2654435761u) >> (32 - 13);
    while (gif->keys[at] != 0) {
        if (gif->keys[at] == key) {
            return gif->codes[at];
        }
        at = (at + 1) & (KG_LZW_TABLE_SIZE - 1);
    }
    *slot = (int)at;
    return -1;
}

/* Adds byte to the string being matched; when the longer string is new, writes the
 * code of the old one, gives the new string the next code and starts over at byte. */
static int kg_lzw_extend(kg_gif* gif, kg_lzw_writer* w, int current, int byte)
{
    int slot = 0;
    int code = kg_lzw_find(gif, current, byte, &slot);
    if (code >= 0) {
        return code;
    }
    kg_lzw_put(w, current, w->code_size);
    gif->keys[slot] = ((int32_t)current << 8 | byte) + 1;
    gif->codes[slot] = (int16_t)w->next_code;
    if (w->next_code >= (1 << w->code_size) && w->code_size < 12) {
        w->code_size++;
    }
    if (++w->next_code > KG_LZW_MAX_CODE) {
        kg_lzw_put(w, KG_LZW_CLEAR, w->code_size);
        kg_lzw_restart(gif, w);
    }
    return byte;
}

/* LZW with 8-bit roots. The code size grows when the next free code no longer fits, and
 * the table restarts with a clear code when it is full, as every decoder expects. */
static void kg_lzw_encode(kg_gif* gif, const uint8_t* pixels, const uint8_t* previous, int stride, int width,
                          int height)
{
    kg_lzw_writer w = {gif->file, 0, 0, {0}, 0, 9, KG_LZW_END + 1};
    kg_lzw_restart(gif, &w);
    kg_lzw_put(&w, KG_LZW_CLEAR, w.code_size);
    int current = -1;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            size_t at = (size_t)y * (size_t)stride + (size_t)x;
            int byte = previous && previous[at] == pixels[at] ? KG_GIF_UNCHANGED : pixels[at];
            current = current < 0 ? byte : kg_lzw_extend(gif, &w, current, byte);
        }
    }
    kg_lzw_put(&w, current, w.code_size);
    kg_lzw_put(&w, KG_LZW_END, w.code_size);
    if (w.bit_count > 0) {
        kg_lzw_put(&w, 0, 8 - w.bit_count);
    }
    kg_lzw_flush_block(&w);
    fputc(0, gif->file); /* block terminator */
}

/* The smallest rectangle holding every pixel that differs from the previous frame; the
 * first frame is whole. Returns 0 when nothing changed. */
static int kg_changed_rect(const kg_gif* gif, const uint8_t* pixels, int rect[4])
{
    int x0 = gif->width, y0 = gif->height, x1 = -1, y1 = -1;
    for (int y = 0; y < gif->height; ++y) {
        const uint8_t* row = pixels + (size_t)y * (size_t)gif->width;
        const uint8_t* old = gif->previous + (size_t)y * (size_t)gif->width;
        for (int x = 0; x < gif->width; ++x) {
            if (gif->frame_count == 0 || row[x] != old[x]) {
                x0 = x < x0 ? x : x0;
                x1 = x > x1 ? x : x1;
                y0 = y < y0 ? y : y0;
                y1 = y;
            }
        }
    }
    rect[0] = x0;
    rect[1] = y0;
    rect[2] = x1 - x0 + 1;
    rect[3] = y1 - y0 + 1;
    return x1 >= 0;
}

int kg_gif_add_frame(kg_gif* gif, const uint8_t* pixels, int delay_cs)
{
    int rect[4];
    if (!kg_changed_rect(gif, pixels, rect)) {
        rect[0] = rect[1] = 0; /* a frame still needs an image: one unchanged pixel */
        rect[2] = rect[3] = 1;
    }
    /* graphic control: keep each frame under the next one (disposal 1), so that the next
     * needs to store only what changed; unchanged pixels become long transparent runs,
     * which LZW packs far better than the picture they cover */
    uint8_t control[8] = {0x21, 0xf9, 4,    0x05, (uint8_t)(delay_cs & 0xff), (uint8_t)((delay_cs >> 8) & 0xff),
                          KG_GIF_UNCHANGED, 0};
    fwrite(control, 1, sizeof control, gif->file);
    fputc(0x2c, gif->file);
    for (int i = 0; i < 4; ++i) {
        kg_put16(gif->file, rect[i]);
    }
    fputc(0, gif->file); /* no local colour table, not interlaced */
    fputc(8, gif->file); /* LZW minimum code size */
    size_t corner = (size_t)rect[1] * (size_t)gif->width + (size_t)rect[0];
    kg_lzw_encode(gif, pixels + corner, gif->frame_count > 0 ? gif->previous + corner : NULL, gif->width, rect[2],
                  rect[3]);
    memcpy(gif->previous, pixels, (size_t)gif->width * (size_t)gif->height);
    gif->frame_count++;
    if (ferror(gif->file)) {
        gif->failed = 1;
    }
    return gif->failed ? -1 : 0;
}

int kg_gif_close(kg_gif* gif)
{
    if (!gif) {
        return -1;
    }
    fputc(0x3b, gif->file);
    int failed = gif->failed || ferror(gif->file);
    failed |= fclose(gif->file) != 0;
    free(gif->previous);
    free(gif);
    return failed ? -1 : 0;
}

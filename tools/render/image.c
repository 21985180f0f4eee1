#include "image.h"
#include "palette.h"

#include <stdlib.h>

/* The stb implementations live in this file only. Debian also ships them built as
 * libstb, but compiling them here keeps the tool working with any copy of the headers. */
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_GIF
#include <stb_image.h>

int kg_write_png_rgb(const char* path, int width, int height, const uint8_t* rgb, int stride)
{
    return stbi_write_png(path, width, height, 3, rgb, stride) ? 0 : -1;
}

int kg_write_png(const char* path, const kg_canvas* canvas)
{
    size_t count = (size_t)canvas->width * (size_t)canvas->height;
    uint8_t* rgb = malloc(count * 3);
    if (!rgb) {
        return -1;
    }
    const uint8_t* palette = kg_palette_rgb();
    for (size_t i = 0; i < count; ++i) {
        const uint8_t* color = palette + 3 * canvas->pixels[i];
        rgb[3 * i + 0] = color[0];
        rgb[3 * i + 1] = color[1];
        rgb[3 * i + 2] = color[2];
    }
    int result = kg_write_png_rgb(path, canvas->width, canvas->height, rgb, canvas->width * 3);
    free(rgb);
    return result;
}

uint8_t* kg_read_png_rgb(const char* path, int* width, int* height)
{
    int channels;
    return stbi_load(path, width, height, &channels, 3);
}

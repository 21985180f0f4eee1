/* PNG support when the build found no stb headers: every call fails with a hint. */
#include "image.h"

#include <stdio.h>

static int kg_no_png(const char* path)
{
    fprintf(stderr, "%s: this build writes no PNG (install libstb-dev and rebuild)\n", path);
    return -1;
}

int kg_write_png(const char* path, const kg_canvas* canvas)
{
    (void)canvas;
    return kg_no_png(path);
}

int kg_write_png_rgb(const char* path, int width, int height, const uint8_t* rgb, int stride)
{
    (void)width;
    (void)height;
    (void)rgb;
    (void)stride;
    return kg_no_png(path);
}

uint8_t* kg_read_png_rgb(const char* path, int* width, int* height)
{
    (void)width;
    (void)height;
    kg_no_png(path);
    return NULL;
}

/* PNG files through stb_image_write and stb_image (Debian: libstb-dev). */
#ifndef KG_RENDER_IMAGE_H
#define KG_RENDER_IMAGE_H

#include "canvas.h"

/* Writes the canvas as an RGB PNG, looking its indices up in the palette. 0 on success. */
int kg_write_png(const char* path, const kg_canvas* canvas);
/* Writes width x height RGB pixels (3 bytes each, rows of stride bytes). 0 on success. */
int kg_write_png_rgb(const char* path, int width, int height, const uint8_t* rgb, int stride);
/* Reads any PNG as RGB: returns malloc'ed width * height * 3 bytes (free() them), or NULL. */
uint8_t* kg_read_png_rgb(const char* path, int* width, int* height);

#endif

/* A compact animated GIF89a writer for palette-index frames: one global 256-colour
 * table, LZW, and only the rectangle that changed since the previous frame is stored,
 * with the unchanged pixels in it transparent, so mostly still scenes make small files.
 * Loops forever. */
#ifndef KG_RENDER_GIF_H
#define KG_RENDER_GIF_H

#include <stdint.h>

typedef struct kg_gif kg_gif;

/* palette: 256 r,g,b triples; frames may not use index 255, which the file uses for
 * "unchanged since the last frame". NULL when the file cannot be created or memory is
 * short. */
kg_gif* kg_gif_open(const char* path, int width, int height, const uint8_t* palette);
/* pixels: width * height indices; delay in hundredths of a second. 0 on success. */
int kg_gif_add_frame(kg_gif* gif, const uint8_t* pixels, int delay_cs);
/* Finishes and closes the file; 0 when everything was written. */
int kg_gif_close(kg_gif* gif);

#endif

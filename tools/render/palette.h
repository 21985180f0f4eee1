/* The renderer's fixed 256-colour palette. Every frame is drawn with palette indices,
 * so a GIF frame is the canvas itself (no quantising) and PNG and screen output only
 * look the colours up. */
#ifndef KG_RENDER_PALETTE_H
#define KG_RENDER_PALETTE_H

#include <stdint.h>

enum {
    KG_COLOR_BACKGROUND = 0,
    KG_COLOR_GRID,
    KG_COLOR_STATIC_FILL,
    KG_COLOR_STATIC_LINE,
    KG_COLOR_KINEMATIC_FILL,
    KG_COLOR_KINEMATIC_LINE,
    KG_COLOR_PARTICLE,
    KG_COLOR_CONTACT,
    KG_COLOR_NORMAL,
    KG_COLOR_AABB,
    KG_COLOR_TEXT,
    KG_COLOR_TEXT_SHADOW,
    KG_COLOR_TILE_FILL,
    KG_COLOR_TILE_LINE,
    KG_COLOR_ONE_WAY_FILL,
    KG_COLOR_ONE_WAY_LINE,
    KG_COLOR_SELECTION,
    KG_COLOR_SENSOR,
    KG_COLOR_HUE_FIRST = 32, /* dynamic bodies: KG_HUE_COUNT pairs (fill, outline) */
    KG_HUE_COUNT = 24
};

typedef struct kg_rgb {
    uint8_t r, g, b;
} kg_rgb;

/* The colour of a palette index. */
kg_rgb kg_palette_color(uint8_t index);
/* The whole palette as 256 r,g,b triples (768 bytes), as GIF and SDL want it. */
const uint8_t* kg_palette_rgb(void);

/* Fill and outline of dynamic body number index: neighbours get distant hues. */
uint8_t kg_hue_fill(uint32_t index);
uint8_t kg_hue_line(uint32_t index);
/* Non-zero when color is the fill of some dynamic body. */
int kg_is_hue_fill(uint8_t color);

#endif

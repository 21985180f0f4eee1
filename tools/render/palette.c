#include "palette.h"

#include <math.h>

static const kg_rgb kFixedColors[] = {
    [KG_COLOR_BACKGROUND] = {0x1c, 0x20, 0x27},
    [KG_COLOR_GRID] = {0x26, 0x2b, 0x34},
    [KG_COLOR_STATIC_FILL] = {0x8b, 0x90, 0x99},
    [KG_COLOR_STATIC_LINE] = {0x5a, 0x5f, 0x68},
    [KG_COLOR_KINEMATIC_FILL] = {0xb9, 0xa6, 0xe0},
    [KG_COLOR_KINEMATIC_LINE] = {0x6e, 0x5a, 0x96},
    [KG_COLOR_PARTICLE] = {0xe8, 0xf4, 0xff},
    [KG_COLOR_CONTACT] = {0xff, 0x3b, 0x30},
    [KG_COLOR_NORMAL] = {0xff, 0xd6, 0x0a},
    [KG_COLOR_AABB] = {0x34, 0xc7, 0x59},
    [KG_COLOR_TEXT] = {0xf2, 0xf2, 0xf2},
    [KG_COLOR_TEXT_SHADOW] = {0x00, 0x00, 0x00},
    [KG_COLOR_TILE_FILL] = {0x6b, 0x5b, 0x4b},
    [KG_COLOR_TILE_LINE] = {0xa8, 0x90, 0x6e},
    [KG_COLOR_ONE_WAY_FILL] = {0x8a, 0x6a, 0x3a},
    [KG_COLOR_ONE_WAY_LINE] = {0xe0, 0xb0, 0x60},
    [KG_COLOR_SELECTION] = {0xff, 0xff, 0xff},
    [KG_COLOR_SENSOR] = {0xf0, 0x7a, 0xf0},
};

static uint8_t kPalette[256 * 3];
static int kPaletteReady;

static kg_rgb kg_hsv(float hue, float saturation, float value)
{
    float h = hue * 6.0f;
    int sector = (int)h % 6;
    float f = h - floorf(h);
    float p = value * (1.0f - saturation), q = value * (1.0f - saturation * f);
    float t = value * (1.0f - saturation * (1.0f - f));
    float rgb[6][3] = {{value, t, p}, {q, value, p}, {p, value, t}, {p, q, value}, {t, p, value}, {value, p, q}};
    return (kg_rgb){(uint8_t)lrintf(rgb[sector][0] * 255.0f), (uint8_t)lrintf(rgb[sector][1] * 255.0f),
                    (uint8_t)lrintf(rgb[sector][2] * 255.0f)};
}

static void kg_palette_set(int index, kg_rgb color)
{
    kPalette[3 * index + 0] = color.r;
    kPalette[3 * index + 1] = color.g;
    kPalette[3 * index + 2] = color.b;
}

static void kg_palette_build(void)
{
    for (int i = 0; i < (int)(sizeof kFixedColors / sizeof kFixedColors[0]); ++i) {
        kg_palette_set(i, kFixedColors[i]);
    }
    for (int h = 0; h < KG_HUE_COUNT; ++h) {
        float hue = (float)h / (float)KG_HUE_COUNT;
        kg_palette_set(KG_COLOR_HUE_FIRST + 2 * h, kg_hsv(hue, 0.55f, 0.95f));
        kg_palette_set(KG_COLOR_HUE_FIRST + 2 * h + 1, kg_hsv(hue, 0.70f, 0.45f));
    }
    kPaletteReady = 1;
}

const uint8_t* kg_palette_rgb(void)
{
    if (!kPaletteReady) {
        kg_palette_build();
    }
    return kPalette;
}

kg_rgb kg_palette_color(uint8_t index)
{
    const uint8_t* p = kg_palette_rgb() + 3 * index;
    return (kg_rgb){p[0], p[1], p[2]};
}

/* A multiplicative hash, so that bodies laid out on a grid (whose row length may be a
 * multiple of the hue count) do not line up in stripes of one colour. */
static uint32_t kg_hue_of(uint32_t index) { return ((index * 2654435761u) >> 16) % KG_HUE_COUNT; }

uint8_t kg_hue_fill(uint32_t index) { return (uint8_t)(KG_COLOR_HUE_FIRST + 2 * kg_hue_of(index)); }
uint8_t kg_hue_line(uint32_t index) { return (uint8_t)(KG_COLOR_HUE_FIRST + 2 * kg_hue_of(index) + 1); }

int kg_is_hue_fill(uint8_t color)
{
    return color >= KG_COLOR_HUE_FIRST && color < KG_COLOR_HUE_FIRST + 2 * KG_HUE_COUNT &&
           (color - KG_COLOR_HUE_FIRST) % 2 == 0;
}

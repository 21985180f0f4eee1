/* kg_png_probe: checks pixel colours of a PNG, for the tests of 'kgyro render' and
 * 'kgyro view' (no image tools needed on the test machine).
 *
 *   kg_png_probe FILE CHECK...
 *     at X Y COLOR            pixel (X, Y) has COLOR
 *     not X Y COLOR           pixel (X, Y) does not have COLOR
 *     any X0 Y0 X1 Y1 COLOR   some pixel with X0 <= x < X1, Y0 <= y < Y1 has COLOR
 *     size W H                the image is W x H
 *   COLOR: background, grid, static, static-line, kinematic, particle, text, tile, one-way,
 *   body (the fill of any dynamic body) or RRGGBB in hex.
 *
 * Prints one line per check; exits 0 when all pass, 1 when one fails, 2 on bad usage. */
#include "image.h"
#include "palette.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct kg_named_color {
    const char* name;
    int index;
} kg_named_color;

static const kg_named_color kNames[] = {
    {"background", KG_COLOR_BACKGROUND}, {"grid", KG_COLOR_GRID},
    {"static", KG_COLOR_STATIC_FILL},    {"static-line", KG_COLOR_STATIC_LINE},
    {"kinematic", KG_COLOR_KINEMATIC_FILL}, {"particle", KG_COLOR_PARTICLE},
    {"text", KG_COLOR_TEXT},             {"tile", KG_COLOR_TILE_FILL},
    {"one-way", KG_COLOR_ONE_WAY_FILL},
};

static int kg_same(kg_rgb a, const uint8_t* b) { return a.r == b[0] && a.g == b[1] && a.b == b[2]; }

/* Whether the pixel p (3 bytes) is COLOR; -1 when COLOR is not a colour. */
static int kg_matches(const char* color, const uint8_t* p)
{
    if (strcmp(color, "body") == 0) {
        for (int h = 0; h < KG_HUE_COUNT; ++h) {
            if (kg_same(kg_palette_color((uint8_t)(KG_COLOR_HUE_FIRST + 2 * h)), p)) {
                return 1;
            }
        }
        return 0;
    }
    for (size_t i = 0; i < sizeof kNames / sizeof kNames[0]; ++i) {
        if (strcmp(color, kNames[i].name) == 0) {
            return kg_same(kg_palette_color((uint8_t)kNames[i].index), p);
        }
    }
    unsigned hex;
    char extra;
    if (strlen(color) != 6 || sscanf(color, "%6x%c", &hex, &extra) != 1) {
        return -1;
    }
    kg_rgb rgb = {(uint8_t)(hex >> 16), (uint8_t)(hex >> 8), (uint8_t)hex};
    return kg_same(rgb, p);
}

typedef struct kg_image {
    uint8_t* rgb;
    int width, height;
} kg_image;

static const uint8_t* kg_pixel(const kg_image* image, int x, int y)
{
    if (x < 0 || y < 0 || x >= image->width || y >= image->height) {
        return NULL;
    }
    return image->rgb + 3 * ((size_t)y * (size_t)image->width + (size_t)x);
}

/* Runs the check at argv[*i], moving *i past it: 1 pass, 0 fail, -1 bad usage. */
static int kg_check(const kg_image* image, int argc, char** argv, int* i)
{
    const char* verb = argv[*i];
    int pass = -1;
    if ((strcmp(verb, "at") == 0 || strcmp(verb, "not") == 0) && *i + 3 < argc) {
        const uint8_t* p = kg_pixel(image, atoi(argv[*i + 1]), atoi(argv[*i + 2]));
        int m = p ? kg_matches(argv[*i + 3], p) : -1;
        pass = m < 0 ? -1 : (verb[0] == 'a' ? m : !m);
        if (p) {
            printf("%s %s %s %s: %02x%02x%02x: %s\n", verb, argv[*i + 1], argv[*i + 2], argv[*i + 3], p[0], p[1], p[2],
                   pass > 0 ? "ok" : "FAILED");
        }
        *i += 4;
    } else if (strcmp(verb, "any") == 0 && *i + 5 < argc) {
        int x0 = atoi(argv[*i + 1]), y0 = atoi(argv[*i + 2]), x1 = atoi(argv[*i + 3]), y1 = atoi(argv[*i + 4]);
        pass = 0;
        for (int y = y0; y < y1 && pass == 0; ++y) {
            for (int x = x0; x < x1 && pass == 0; ++x) {
                const uint8_t* p = kg_pixel(image, x, y);
                pass = p ? kg_matches(argv[*i + 5], p) : pass;
            }
        }
        printf("any %d %d %d %d %s: %s\n", x0, y0, x1, y1, argv[*i + 5], pass > 0 ? "ok" : "FAILED");
        *i += 6;
    } else if (strcmp(verb, "size") == 0 && *i + 2 < argc) {
        pass = image->width == atoi(argv[*i + 1]) && image->height == atoi(argv[*i + 2]);
        printf("size %dx%d: %s\n", image->width, image->height, pass ? "ok" : "FAILED");
        *i += 3;
    }
    return pass;
}

int main(int argc, char** argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: kg_png_probe FILE CHECK... (see the source for the checks)\n");
        return 2;
    }
    kg_image image;
    image.rgb = kg_read_png_rgb(argv[1], &image.width, &image.height);
    if (!image.rgb) {
        fprintf(stderr, "kg_png_probe: cannot read %s as PNG\n", argv[1]);
        return 1;
    }
    int status = 0;
    for (int i = 2; i < argc && status != 2;) {
        int pass = kg_check(&image, argc, argv, &i);
        if (pass < 0) {
            fprintf(stderr, "kg_png_probe: bad check at '%s'\n", argv[i < argc ? i : argc - 1]);
            status = 2;
        } else if (pass == 0) {
            status = 1;
        }
    }
    free(image.rgb);
    return status;
}

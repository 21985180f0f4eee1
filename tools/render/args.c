#include "args.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int kg_option_value(const char* command, int argc, char** argv, int* i, const char* const* names,
                    const char** value)
{
    int known = 0;
    for (const char* const* name = names; *name && !known; ++name) {
        known = strcmp(argv[*i], *name) == 0;
    }
    if (!known) {
        return 0;
    }
    if (*i + 1 >= argc) {
        fprintf(stderr, "%s: %s needs a value\n", command, argv[*i]);
        return -1;
    }
    *value = argv[++*i];
    return 1;
}

int kg_parse_int(const char* text, int low, int high, int* out)
{
    char* end;
    errno = 0;
    long value = strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || value < low || value > high) {
        return -1;
    }
    *out = (int)value;
    return 0;
}

int kg_parse_size(const char* text, int* width, int* height)
{
    int w, h, used = 0;
    if (sscanf(text, "%dx%d%n", &w, &h, &used) != 2 || text[used] != '\0' || w < 16 || h < 16 || w > 8192 ||
        h > 8192) {
        return -1;
    }
    *width = w;
    *height = h;
    return 0;
}

int kg_parse_box(const char* text, kg_aabb* out)
{
    float x0, y0, x1, y1;
    int used = 0;
    if (sscanf(text, "%f,%f,%f,%f%n", &x0, &y0, &x1, &y1, &used) != 4 || text[used] != '\0' || !isfinite(x0) ||
        !isfinite(y0) || !isfinite(x1) || !isfinite(y1) || !(x1 > x0) || !(y1 > y0)) {
        return -1;
    }
    *out = (kg_aabb){{x0, y0}, {x1, y1}};
    return 0;
}

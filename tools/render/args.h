/* Parsing the options the render and view commands share. The value parsers return 0
 * on success and -1 (leaving *out alone) when text is not a valid value. */
#ifndef KG_RENDER_ARGS_H
#define KG_RENDER_ARGS_H

#include "kgyro/types.h"

/* When argv[*i] is one of names (a NULL-terminated list), stores the argument after it
 * in *value, moves *i to it and returns 1; returns 0 when argv[*i] is not one of names,
 * and -1, after saying so on stderr after command, when the value is missing. */
int kg_option_value(const char* command, int argc, char** argv, int* i, const char* const* names,
                    const char** value);

/* An integer in [low, high]. */
int kg_parse_int(const char* text, int low, int high, int* out);
/* "WxH", both in [16, 8192]. */
int kg_parse_size(const char* text, int* width, int* height);
/* "X0,Y0,X1,Y1" in metres, a box with X1 > X0 and Y1 > Y0. */
int kg_parse_box(const char* text, kg_aabb* out);

#endif

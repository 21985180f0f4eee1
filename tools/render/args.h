/* Parsing the option values the render and view commands share. Each returns 0 on
 * success and -1 (leaving *out alone) when text is not a valid value. */
#ifndef KG_RENDER_ARGS_H
#define KG_RENDER_ARGS_H

#include "kgyro/types.h"

/* An integer in [low, high]. */
int kg_parse_int(const char* text, int low, int high, int* out);
/* "WxH", both in [16, 8192]. */
int kg_parse_size(const char* text, int* width, int* height);
/* "X0,Y0,X1,Y1" in metres, a box with X1 > X0 and Y1 > Y0. */
int kg_parse_box(const char* text, kg_aabb* out);

#endif

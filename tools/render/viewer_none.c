/* 'kgyro view' in a build without SDL2. */
#include "viewer.h"

#include <stdio.h>

int kg_view_run(const kg_view_config* config)
{
    (void)config;
    fprintf(stderr, "kgyro view: this build has no SDL2 (install libsdl2-dev and rebuild)\n");
    return 1;
}

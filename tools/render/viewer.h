/* The interactive viewer behind 'kgyro view' (SDL2). */
#ifndef KG_RENDER_VIEWER_H
#define KG_RENDER_VIEWER_H

#include "kgyro/kgyro.h"

typedef struct kg_view_config {
    const char* scene;      /* a scene file or a generator name */
    uint32_t seed;
    int max_bodies;         /* the most a scene file may ask for; -1: no limit */
    kg_backend backend;
    int width, height;      /* window size */
    int frames;             /* exit after this many frames; 0 = run until closed */
    const char* screenshot; /* PNG of the last frame shown, or NULL */
    const char* script;     /* scripted input, see kgyro view --help; or NULL */
    int has_view;
    kg_aabb view;           /* world box shown first when has_view */
} kg_view_config;

/* Runs the window until it is closed or config->frames have been shown. Returns the
 * process exit code (0, 1 failure, 2 bad scene or script). */
int kg_view_run(const kg_view_config* config);

#endif

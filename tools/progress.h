/* The progress line of the long-running commands (run, render, bench): on a terminal,
 * one line on stderr with the percentage done, steps a second and the time left,
 * redrawn at most four times a second and erased at the end; nothing at all when stderr
 * is not a terminal, so that logs, pipes and tests see no trace of it. */
#ifndef KG_TOOLS_PROGRESS_H
#define KG_TOOLS_PROGRESS_H

#include <stddef.h>
#include <stdio.h>

typedef struct kg_progress {
    FILE* out;         /* NULL: silent */
    const char* label; /* what the line starts with, e.g. "kgyro run: rain_1000" */
    long total;        /* steps in all */
    double start_s;    /* when started, monotonic seconds */
    double drawn_s;    /* when last drawn */
    int shown;         /* a line is on screen */
} kg_progress;

/* Starts a progress line on stderr when it is a terminal; silent otherwise. label must
 * live until kg_progress_end. */
void kg_progress_start(kg_progress* p, const char* label, long total);
/* The same on out whatever it is (NULL: silent): for tests. */
void kg_progress_start_on(kg_progress* p, FILE* out, const char* label, long total);
/* done steps of total are done. Cheap enough to call every step: it draws only when
 * the run has gone on for half a second and a quarter second has passed since the last
 * line. */
void kg_progress_update(kg_progress* p, long done);
/* Erases the line, if one was drawn. */
void kg_progress_end(kg_progress* p);

/* The line's text: "LABEL: 25% 500 steps/s, 1.5 s left" for 250 of 1000 steps done in
 * elapsed_s = 0.5. */
void kg_progress_format(char* out, size_t size, const char* label, long done, long total, double elapsed_s);

#endif

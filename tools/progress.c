#include "progress.h"

#include <time.h>
#include <unistd.h>

/* A run shorter than this never shows a line: it would only flicker. */
#define KG_PROGRESS_DELAY_S 0.5
/* At most four lines a second: more is unreadable and costs the run time. */
#define KG_PROGRESS_PERIOD_S 0.25

static double kg_progress_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void kg_progress_start_on(kg_progress* p, FILE* out, const char* label, long total)
{
    p->out = out;
    p->label = label;
    p->total = total > 0 ? total : 1;
    p->start_s = kg_progress_now();
    p->drawn_s = p->start_s;
    p->shown = 0;
}

void kg_progress_start(kg_progress* p, const char* label, long total)
{
    kg_progress_start_on(p, isatty(fileno(stderr)) ? stderr : NULL, label, total);
}

void kg_progress_format(char* out, size_t size, const char* label, long done, long total, double elapsed_s)
{
    double rate = elapsed_s > 0.0 ? (double)done / elapsed_s : 0.0;
    double left_s = rate > 0.0 ? (double)(total - done) / rate : 0.0;
    snprintf(out, size, "%s: %ld%% %.0f steps/s, %.1f s left", label, total > 0 ? 100 * done / total : 0, rate,
             left_s);
}

void kg_progress_update(kg_progress* p, long done)
{
    if (!p->out) {
        return;
    }
    double now = kg_progress_now();
    if (now - p->start_s < KG_PROGRESS_DELAY_S || now - p->drawn_s < KG_PROGRESS_PERIOD_S) {
        return;
    }
    char line[256];
    kg_progress_format(line, sizeof line, p->label, done, p->total, now - p->start_s);
    /* \r back to the start of the line, ESC [K erases what a longer line left */
    fprintf(p->out, "\r%s\033[K", line);
    fflush(p->out);
    p->drawn_s = now;
    p->shown = 1;
}

void kg_progress_end(kg_progress* p)
{
    if (p->out && p->shown) {
        fputs("\r\033[K", p->out);
        fflush(p->out);
    }
    p->shown = 0;
}

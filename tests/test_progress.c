/* The progress line of kgyro run, render and bench (tools/progress.c): its text, its
 * silence off a terminal, its rate limit and its erasure. */
#include "kg_test.h"

#include "progress.h"

#include <string.h>
#include <time.h>
#include <unistd.h>

static void test_format(void)
{
    char line[128];
    kg_progress_format(line, sizeof line, "kgyro run: rain_1000", 250, 1000, 0.5);
    KG_CHECK(strcmp(line, "kgyro run: rain_1000: 25% 500 steps/s, 1.5 s left") == 0);
    kg_progress_format(line, sizeof line, "x", 0, 10, 0.0); /* nothing done yet: no rate */
    KG_CHECK(strcmp(line, "x: 0% 0 steps/s, 0.0 s left") == 0);
}

/* ctest's stderr is a pipe or a file, never a terminal: the line is off. */
static void test_silent_off_a_terminal(void)
{
    kg_progress p;
    kg_progress_start(&p, "test", 100);
    KG_CHECK(isatty(fileno(stderr)) || p.out == NULL);
}

static void kg_sleep_s(double seconds)
{
    struct timespec t = {(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
    nanosleep(&t, NULL);
}

static long kg_count(const char* text, const char* what)
{
    long n = 0;
    for (const char* at = strstr(text, what); at; at = strstr(at + 1, what)) {
        n++;
    }
    return n;
}

/* Nothing in the first half second; then one line, not another within a quarter
 * second; the end erases it. */
static void test_draws_rarely_and_erases(void)
{
    FILE* out = tmpfile();
    KG_CHECK(out != NULL);
    if (!out) {
        return;
    }
    kg_progress p;
    kg_progress_start_on(&p, out, "job", 100);
    kg_progress_update(&p, 10);
    KG_CHECK(ftell(out) == 0);
    kg_sleep_s(0.6);
    kg_progress_update(&p, 50);
    kg_progress_update(&p, 51);
    kg_progress_end(&p);
    char text[512] = "";
    rewind(out);
    size_t n = fread(text, 1, sizeof text - 1, out);
    text[n] = '\0';
    KG_CHECK(kg_count(text, "job: 50% ") == 1);
    KG_CHECK(kg_count(text, "job: ") == 1);
    KG_CHECK(n >= 4 && strcmp(text + n - 4, "\r\033[K") == 0);
    fclose(out);
}

KG_TEST_MAIN(KG_TEST(test_format), KG_TEST(test_silent_off_a_terminal), KG_TEST(test_draws_rarely_and_erases))

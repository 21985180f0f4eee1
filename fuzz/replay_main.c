/* Replays saved inputs through a fuzz target without libFuzzer, so that every crash
 * the fuzzer ever found, and the seed corpus, run as an ordinary ctest in every build
 * (release and ASan+UBSan alike).
 *
 *   replay PATH...   each PATH a file, or a directory whose regular files are replayed;
 *                    a directory that does not exist is empty (tests/regress/NAME
 *                    appears with the first crash of target NAME)
 *
 * Each input runs in a child process, so one that aborts (a broken contract, a
 * sanitizer report, a leak found at the child's exit) does not hide the others: every
 * failing input is named. Exit status 1 when any input fails, a file cannot be read or
 * no input was found at all (a misconfigured test must not pass). */
#include "fuzz_common.h"

#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* Runs one input in a child; exit() there, not _exit(), so LeakSanitizer checks it.
 * Returns the child's wait status, or -1 when it could not be run. */
static int run_isolated(const uint8_t* data, size_t size)
{
    fflush(NULL);
    pid_t child = fork();
    if (child < 0) {
        perror("replay: fork");
        return -1;
    }
    if (child == 0) {
        LLVMFuzzerTestOneInput(data, size);
        exit(0);
    }
    int status = 0;
    if (waitpid(child, &status, 0) != child) {
        perror("replay: waitpid");
        return -1;
    }
    return status;
}

static int report_status(const char* path, int status)
{
    if (status == 0) {
        return 1;
    }
    if (status > 0 && WIFSIGNALED(status)) {
        fprintf(stderr, "replay: FAILED on %s (signal %d, %s)\n", path, WTERMSIG(status), strsignal(WTERMSIG(status)));
    } else {
        fprintf(stderr, "replay: FAILED on %s (exit status %d)\n", path, status > 0 ? WEXITSTATUS(status) : -1);
    }
    return 0;
}

static int replay_file(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return 0;
    }
    uint8_t* data = NULL;
    size_t size = 0, capacity = 0;
    for (;;) {
        if (size == capacity) {
            capacity = capacity ? 2 * capacity : 4096;
            uint8_t* grown = realloc(data, capacity);
            if (!grown) {
                free(data);
                fclose(f);
                fprintf(stderr, "replay: out of memory reading %s\n", path);
                return 0;
            }
            data = grown;
        }
        size_t got = fread(data + size, 1, capacity - size, f);
        if (got == 0) {
            break;
        }
        size += got;
    }
    fclose(f);
    int status = run_isolated(data, size);
    free(data);
    return report_status(path, status);
}

static int is_regular_file(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Replays the regular files of a directory; hidden files (.gitkeep) are not inputs. */
static int replay_directory(const char* dir_path, int* replayed)
{
    DIR* dir = opendir(dir_path);
    if (!dir) {
        fprintf(stderr, "replay: cannot open %s\n", dir_path);
        return 0;
    }
    int ok = 1;
    struct dirent* entry;
    while ((entry = readdir(dir)) != NULL) {
        if (entry->d_name[0] == '.') {
            continue;
        }
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir_path, entry->d_name);
        if (is_regular_file(path)) {
            ok = replay_file(path) && ok;
            *replayed += 1;
        }
    }
    closedir(dir);
    return ok;
}

int main(int argc, char** argv)
{
    int ok = 1, replayed = 0;
    for (int i = 1; i < argc; ++i) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            printf("replay: %s does not exist, nothing to replay there\n", argv[i]);
        } else if (S_ISDIR(st.st_mode)) {
            ok = replay_directory(argv[i], &replayed) && ok;
        } else {
            ok = replay_file(argv[i]) && ok;
            replayed += 1;
        }
    }
    printf("replayed %d inputs\n", replayed);
    return ok && replayed > 0 ? 0 : 1;
}

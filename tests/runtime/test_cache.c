/* The disk cache of compiled programs (runtime/src/program_cache.c): a
 * second build of the same program loads the stored binary; a damaged
 * entry (cut short, empty, a flipped bit, trailing bytes, not an entry, a
 * named pipe or a directory) is removed with a one-line notice and
 * rebuilt, never handed to the implementation; processes and threads
 * building the same program at once compile it once and leave one whole
 * entry and no other file; a held build lock is waited for, a stale one is
 * not; PoCL's fast builds are not stored however long a loaded machine
 * makes them; PERMA_CACHE_DIR=off
 * writes nothing.  PERMA_CACHE_MIN_SECONDS=0 stores every program, PoCL's
 * included. */
#define _DEFAULT_SOURCE /* flock */
#include "perma_test.h"
#include "tree_procedure.h"

#include <CL/cl.h>
#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <utime.h>

static char dir[64];

/* Paths in the cache directory. */
#define PATH_MAX_LENGTH 512
#define CACHE_MAGIC "perma program cache 2\n"

/* What one build and run of the tree saw. */
typedef struct built {
    perma_build_info info;
    char log[4096]; /* notices and warnings (config.build_log) */
} built;

static void collect_log(void *user, const char *text)
{
    built *b = user;
    size_t used = strlen(b->log);
    snprintf(b->log + used, sizeof b->log - used, "%s", text);
}

/* Build and run a depth-8 tree, checking its counts; build_options makes
 * another program.  Returns 0, or the line where it failed (for builders
 * in other processes and threads, which report to the test). */
static int try_tree(const char *build_options, built *out)
{
    memset(out, 0, sizeof *out);
    perma_config config;
    perma_config_init(&config);
    config.build_options = build_options;
    config.time_limit = 120;
    config.build_log = collect_log;
    config.build_log_user = out;
    perma_runtime *rt = NULL;
    perma_error error;
    if (perma_create(&config, &rt, &error) != PERMA_OK) {
        snprintf(out->log, sizeof out->log, "perma_create: %s\n", error.message);
        return __LINE__;
    }
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 1, counts, sums); /* fails the test itself */
    struct tree_node root = { 0, 8, 1, 0 };
    int failed = 0;
    if (perma_seed(rt, id, &root, 1) != PERMA_OK)
        failed = __LINE__;
    else if (perma_run(rt) != PERMA_OK)
        failed = __LINE__;
    else if (counts[0] != 256 || counts[1] != 255)
        failed = __LINE__;
    if (!failed && perma_get_build_info(rt, &out->info) != PERMA_OK)
        failed = __LINE__;
    if (failed)
        snprintf(out->log + strlen(out->log), sizeof out->log - strlen(out->log), "failed: %s\n", perma_errmsg(rt));
    perma_destroy(rt);
    return failed;
}

static void run_tree(const char *build_options, built *out)
{
    int line = try_tree(build_options, out);
    ck_assert_msg(line == 0, "the tree failed at line %d: %s", line, out->log);
}

/* The entries in the cache directory (every file must be one: no
 * temporary or lock file is left); the path of the last in *path. */
static unsigned entries(char *path, size_t size)
{
    unsigned n = 0;
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        size_t length = strlen(e->d_name);
        ck_assert_msg(length > 4 && strcmp(e->d_name + length - 4, ".bin") == 0, "stray file %s in the cache",
                      e->d_name);
        ck_assert_int_lt(snprintf(path, size, "%s/%s", dir, e->d_name), (int)size);
        ++n;
    }
    closedir(d);
    return n;
}

/* The one entry of the cache, its size and its header's key and binary
 * lengths. */
static void one_entry(char *path, size_t size, off_t *bytes, uint64_t *key_length, uint64_t *binary_length)
{
    ck_assert_uint_eq(entries(path, size), 1);
    FILE *f = fopen(path, "rb");
    ck_assert_ptr_nonnull(f);
    char magic[64];
    ck_assert_ptr_nonnull(fgets(magic, sizeof magic, f));
    ck_assert_str_eq(magic, CACHE_MAGIC);
    uint64_t header[3];
    ck_assert_uint_eq(fread(header, sizeof header, 1, f), 1);
    ck_assert_int_eq(fclose(f), 0);
    struct stat st;
    ck_assert_int_eq(stat(path, &st), 0);
    *bytes = st.st_size;
    *key_length = header[0];
    *binary_length = header[1];
    ck_assert_uint_eq((uint64_t)st.st_size, strlen(CACHE_MAGIC) + sizeof header + header[0] + header[1]);
}

static void remove_all(void)
{
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    struct dirent *e;
    char path[PATH_MAX_LENGTH];
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        unlink(path);
    }
    closedir(d);
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/perma-cache-test.XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(dir));
    setenv("PERMA_CACHE_DIR", dir, 1);
    setenv("PERMA_CACHE_MIN_SECONDS", "0", 1);
}

static void teardown(void)
{
    remove_all();
    rmdir(dir);
    unsetenv("PERMA_CACHE_DIR");
    unsetenv("PERMA_CACHE_MIN_SECONDS");
}

START_TEST(second_build_loads_the_binary)
{
    char path[PATH_MAX_LENGTH];
    built b;
    run_tree(NULL, &b);
    ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_COMPILED);
    ck_assert_int_eq(b.info.stored, 1);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    /* Loading marks the entry used (its time) but does not rewrite it (its
     * inode); a rebuild from source would store a new file. */
    struct utimbuf old = { 1000, 1000 };
    ck_assert_int_eq(utime(path, &old), 0);
    struct stat before, after;
    ck_assert_int_eq(stat(path, &before), 0);
    run_tree(NULL, &b);
    ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_CACHED);
    ck_assert_int_eq(b.info.stored, 0);
    ck_assert_str_eq(b.log, "");
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    ck_assert_int_eq(stat(path, &after), 0);
    ck_assert_uint_eq(after.st_ino, before.st_ino);
    ck_assert_int_gt(after.st_mtime, 1000);

    /* Other build options: another program, another entry. */
    run_tree("-DUNUSED_MACRO=1", &b);
    ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_COMPILED);
    ck_assert_uint_eq(entries(path, sizeof path), 2);
}
END_TEST

/* Flip one bit of the file at `offset`. */
static void flip_bit(const char *path, off_t offset)
{
    FILE *f = fopen(path, "r+b");
    ck_assert_ptr_nonnull(f);
    ck_assert_int_eq(fseeko(f, offset, SEEK_SET), 0);
    int c = fgetc(f);
    ck_assert_int_ne(c, EOF);
    ck_assert_int_eq(fseeko(f, offset, SEEK_SET), 0);
    ck_assert_int_ne(fputc(c ^ 0x10, f), EOF);
    ck_assert_int_eq(fclose(f), 0);
}

static void append_bytes(const char *path, const char *bytes)
{
    FILE *f = fopen(path, "ab");
    ck_assert_ptr_nonnull(f);
    ck_assert_int_ge(fputs(bytes, f), 0);
    ck_assert_int_eq(fclose(f), 0);
}

static void replace_with(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    ck_assert_ptr_nonnull(f);
    ck_assert_int_ge(fputs(text, f), 0);
    ck_assert_int_eq(fclose(f), 0);
}

/* Each damage, done to a sound entry, must give the notice with its reason
 * and a program built from source (PoCL aborts in
 * clCreateProgramWithBinary on an entry cut in half); the entry is then
 * stored again and the next build loads it without a word. */
START_TEST(damaged_entries_are_discarded_and_rebuilt)
{
    enum { HALF, EMPTY, BINARY_BIT, KEY_BIT, HEADER_LENGTH, TRAILING, NOT_AN_ENTRY, KINDS };
    static const char *const reason[KINDS] = {
        "cut short", "an empty file", "checksum does not match", "checksum does not match", "cut short",
        "bytes after its end", "not a program-cache entry",
    };
    char path[PATH_MAX_LENGTH];
    built b;
    run_tree(NULL, &b);
    for (int kind = 0; kind < KINDS; ++kind) {
        off_t bytes;
        uint64_t key_length, binary_length;
        one_entry(path, sizeof path, &bytes, &key_length, &binary_length);
        off_t key_at = (off_t)(strlen(CACHE_MAGIC) + 24);
        switch (kind) {
        case HALF: ck_assert_int_eq(truncate(path, bytes / 2), 0); break;
        case EMPTY: ck_assert_int_eq(truncate(path, 0), 0); break;
        case BINARY_BIT: flip_bit(path, key_at + (off_t)key_length + (off_t)binary_length / 2); break;
        case KEY_BIT: flip_bit(path, key_at + (off_t)key_length / 2); break;
        case HEADER_LENGTH: flip_bit(path, key_at - 16 + 3); break; /* the binary's length grows by 2^27 */
        case TRAILING: append_bytes(path, "trailing bytes"); break;
        case NOT_AN_ENTRY: replace_with(path, "a text file where an entry should be\n"); break;
        }
        run_tree(NULL, &b);
        ck_assert_msg(strstr(b.log, "perma: discarded the damaged program-cache entry") && strstr(b.log, path)
                          && strstr(b.log, reason[kind]),
                      "damage %d: expected a notice naming %s and '%s', got: %s", kind, path, reason[kind], b.log);
        ck_assert_msg(strchr(b.log, '\n') == b.log + strlen(b.log) - 1, "not one line: %s", b.log);
        ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_COMPILED);
        ck_assert_int_eq(b.info.stored, 1);
        run_tree(NULL, &b);
        ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_CACHED);
        ck_assert_str_eq(b.log, "");
    }
}
END_TEST

/* Start `n` processes that build the same program at once; the origins
 * they report must be one compile and n - 1 loads. */
START_TEST(concurrent_processes_compile_once)
{
    enum { N = 3 };
    int go[2], report[2];
    ck_assert_int_eq(pipe(go), 0);
    ck_assert_int_eq(pipe(report), 0);
    pid_t children[N];
    for (int i = 0; i < N; ++i) {
        children[i] = fork();
        ck_assert_int_ge(children[i], 0);
        if (children[i] == 0) {
            char start;
            close(go[1]);
            if (read(go[0], &start, 1) != 0) /* EOF: everyone starts */
                _exit(90);
            built b;
            int line = try_tree(NULL, &b);
            int origin = line ? -line : (int)b.info.origin;
            _exit(write(report[1], &origin, sizeof origin) == sizeof origin ? 0 : 91);
        }
    }
    close(go[0]);
    close(go[1]);
    close(report[1]);
    int compiled = 0, cached = 0;
    for (int i = 0; i < N; ++i) {
        int origin = 0;
        ck_assert_int_eq(read(report[0], &origin, sizeof origin), (int)sizeof origin);
        ck_assert_msg(origin > 0, "a builder failed at line %d", -origin);
        compiled += origin == PERMA_PROGRAM_COMPILED;
        cached += origin == PERMA_PROGRAM_CACHED;
    }
    for (int i = 0; i < N; ++i) {
        int status;
        ck_assert_int_eq(waitpid(children[i], &status, 0), children[i]);
        ck_assert_msg(WIFEXITED(status) && WEXITSTATUS(status) == 0, "builder %d: status %d", i, status);
    }
    close(report[0]);
    ck_assert_int_eq(compiled, 1);
    ck_assert_int_eq(cached, N - 1);
    char path[PATH_MAX_LENGTH];
    off_t bytes;
    uint64_t key_length, binary_length;
    one_entry(path, sizeof path, &bytes, &key_length, &binary_length);
}
END_TEST

typedef struct thread_build {
    pthread_barrier_t *start;
    built b;
    int failed;
} thread_build;

static void *build_in_thread(void *arg)
{
    thread_build *t = arg;
    pthread_barrier_wait(t->start);
    t->failed = try_tree(NULL, &t->b);
    return NULL;
}

/* Threads of one process (reyes-render --devices) likewise.  (PoCL's
 * platform is set up once first: its first clGetPlatformIDs from two
 * threads at once may find no device or crash.) */
START_TEST(concurrent_threads_compile_once)
{
    enum { N = 2 };
    perma_destroy(test_runtime(0, 0, 0));
    pthread_barrier_t start;
    ck_assert_int_eq(pthread_barrier_init(&start, NULL, N), 0);
    thread_build t[N];
    pthread_t threads[N];
    for (int i = 0; i < N; ++i) {
        t[i].start = &start;
        ck_assert_int_eq(pthread_create(&threads[i], NULL, build_in_thread, &t[i]), 0);
    }
    int compiled = 0;
    for (int i = 0; i < N; ++i) {
        ck_assert_int_eq(pthread_join(threads[i], NULL), 0);
        ck_assert_msg(t[i].failed == 0, "thread %d failed at line %d: %s", i, t[i].failed, t[i].b.log);
        compiled += t[i].b.info.origin == PERMA_PROGRAM_COMPILED;
    }
    pthread_barrier_destroy(&start);
    ck_assert_int_eq(compiled, 1);
    char path[PATH_MAX_LENGTH];
    off_t bytes;
    uint64_t key_length, binary_length;
    one_entry(path, sizeof path, &bytes, &key_length, &binary_length);
}
END_TEST

typedef struct held_lock {
    int fd;
    double seconds;
} held_lock;

static void *release_later(void *arg)
{
    held_lock *h = arg;
    struct timespec pause = { (time_t)h->seconds, (long)((h->seconds - (double)(time_t)h->seconds) * 1e9) };
    nanosleep(&pause, NULL);
    close(h->fd); /* lets go of the lock */
    return NULL;
}

/* The lock file of the (one) entry: NAME.lock for NAME.bin. */
static void lock_path_of(const char *entry, char *out, size_t size)
{
    ck_assert_int_lt(snprintf(out, size, "%.*s.lock", (int)(strlen(entry) - 4), entry), (int)size);
}

/* A builder waits while another holds the entry's build lock, and not for
 * a lock file nobody holds (its holder died); no lock file is left. */
START_TEST(held_lock_is_waited_for_and_stale_one_is_not)
{
    char path[PATH_MAX_LENGTH], lock[PATH_MAX_LENGTH];
    built b;
    run_tree(NULL, &b);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    lock_path_of(path, lock, sizeof lock);

    ck_assert_int_eq(unlink(path), 0);
    held_lock h = { open(lock, O_RDWR | O_CREAT, 0600), 1.5 };
    ck_assert_int_ge(h.fd, 0);
    ck_assert_int_eq(flock(h.fd, LOCK_EX), 0);
    pthread_t releaser;
    ck_assert_int_eq(pthread_create(&releaser, NULL, release_later, &h), 0);
    run_tree(NULL, &b);
    ck_assert_int_eq(pthread_join(releaser, NULL), 0);
    ck_assert_msg(b.info.wait_seconds >= 1.4, "waited %g s for a lock held 1.5 s", b.info.wait_seconds);
    ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_COMPILED);
    ck_assert_uint_eq(entries(path, sizeof path), 1);

    ck_assert_int_eq(unlink(path), 0);
    int stale = open(lock, O_RDWR | O_CREAT, 0600);
    ck_assert_int_ge(stale, 0);
    ck_assert_int_eq(close(stale), 0);
    run_tree(NULL, &b);
    ck_assert_msg(b.info.wait_seconds < 1.0, "waited %g s for a lock nobody held", b.info.wait_seconds);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
}
END_TEST

/* The temporary file of a writer that died is removed at the next store
 * once it is an hour old; a young one (a writer at work) is left alone. */
START_TEST(stale_temporary_files_are_removed)
{
    char old[PATH_MAX_LENGTH], young[PATH_MAX_LENGTH], path[PATH_MAX_LENGTH];
    snprintf(old, sizeof old, "%s/0123456789abcdef.tmp.AbCdEf", dir);
    snprintf(young, sizeof young, "%s/fedcba9876543210.tmp.GhIjKl", dir);
    replace_with(old, "half an entry");
    replace_with(young, "half an entry");
    struct utimbuf two_hours_ago = { time(NULL) - 7200, time(NULL) - 7200 };
    ck_assert_int_eq(utime(old, &two_hours_ago), 0);
    built b;
    run_tree(NULL, &b);
    ck_assert_int_ne(access(old, F_OK), 0);
    ck_assert_int_eq(access(young, F_OK), 0);
    ck_assert_int_eq(unlink(young), 0);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
}
END_TEST

/* Whether the runtime runs on PoCL. */
static bool on_pocl(perma_runtime *rt)
{
    cl_platform_id platform;
    char name[256] = "";
    if (clGetDeviceInfo(perma_cl_device(rt), CL_DEVICE_PLATFORM, sizeof platform, &platform, NULL) != CL_SUCCESS)
        return false;
    clGetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof name - 1, name, NULL);
    return strstr(name, "Portable Computing Language") != NULL;
}

/* Issue 23.6: on a loaded machine PoCL's 0.1 s build took over a second,
 * was stored, and asking PoCL for the binary compiled every kernel once
 * more inside perma_build (minutes at load 8, no watchdog, no message).
 * Here a builder gets 5 ms of every 155 (SIGSTOP, SIGCONT): its build
 * takes over PERMA_CACHE_MIN_SECONDS (0.3) of wall time and less of CPU
 * time, and nothing may be stored.  (Elsewhere
 * than on PoCL a build that used a second of CPU time may be stored.)
 * The builder is another process: OpenCL must not be set up in a process
 * that forks. */
START_TEST(slow_wall_time_alone_stores_nothing)
{
    setenv("PERMA_CACHE_MIN_SECONDS", "0.3", 1);
    int report[2];
    ck_assert_int_eq(pipe(report), 0);
    pid_t child = fork();
    ck_assert_int_ge(child, 0);
    if (child == 0) {
        close(report[0]);
        built b;
        int line = try_tree(NULL, &b);
        perma_runtime *rt = test_runtime(0, 0, 0);
        double result[4] = { line ? -line : (double)b.info.origin, b.info.seconds, (double)b.info.stored,
                             on_pocl(rt) };
        perma_destroy(rt);
        _exit(write(report[1], result, sizeof result) == sizeof result ? 0 : 91);
    }
    close(report[1]);
    fcntl(report[0], F_SETFL, O_NONBLOCK);
    double result[4];
    ssize_t got;
    while ((got = read(report[0], result, sizeof result)) < 0) {
        const struct timespec stopped = { 0, 150000000 }, running = { 0, 5000000 };
        kill(child, SIGSTOP);
        nanosleep(&stopped, NULL);
        kill(child, SIGCONT);
        nanosleep(&running, NULL);
    }
    kill(child, SIGCONT);
    int status;
    ck_assert_int_eq(waitpid(child, &status, 0), child);
    ck_assert_int_eq(got, (ssize_t)sizeof result);
    ck_assert_msg(result[0] > 0, "the builder failed at line %g", -result[0]);
    ck_assert_msg(result[1] > 0.3, "the build took only %g s of wall time", result[1]);
    if (result[3] == 0.0) {
        printf("slow_wall_time_alone_stores_nothing: not on PoCL, nothing to check\n");
        return;
    }
    char path[PATH_MAX_LENGTH];
    ck_assert_msg(result[2] == 0.0 && entries(path, sizeof path) == 0,
                  "a %g s build (little CPU time) was stored", result[1]);
}
END_TEST

START_TEST(off_writes_nothing)
{
    char path[PATH_MAX_LENGTH];
    setenv("PERMA_CACHE_DIR", "off", 1);
    built b;
    run_tree(NULL, &b);
    ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_COMPILED);
    setenv("PERMA_CACHE_DIR", dir, 1);
    ck_assert_uint_eq(entries(path, sizeof path), 0);
}
END_TEST

/* An entry that is a named pipe is not opened for reading, which waits
 * for a writer (perma_build hung there): it is discarded like a damaged
 * entry, the program built from source and stored in its place.  An
 * empty directory there the same. */
START_TEST(entries_that_are_not_files_are_discarded)
{
    char path[PATH_MAX_LENGTH];
    built b;
    run_tree(NULL, &b);
    for (int directory = 0; directory < 2; ++directory) {
        ck_assert_uint_eq(entries(path, sizeof path), 1);
        ck_assert_int_eq(unlink(path), 0);
        ck_assert_int_eq(directory ? mkdir(path, 0700) : mkfifo(path, 0600), 0);
        alarm(60); /* a hang fails the test rather than waiting for Check's timeout */
        run_tree(NULL, &b);
        alarm(0);
        char expected[PATH_MAX_LENGTH + 128];
        snprintf(expected, sizeof expected, "perma: discarded the damaged program-cache entry %s (%s, not a file); "
                 "building the program from source\n", path, directory ? "a directory" : "a named pipe");
        ck_assert_str_eq(b.log, expected);
        ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_COMPILED);
        ck_assert_int_eq(b.info.stored, 1);
        run_tree(NULL, &b);
        ck_assert_int_eq(b.info.origin, PERMA_PROGRAM_CACHED);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cache");
    TCase *tc = tcase_create("cache");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, second_build_loads_the_binary);
    tcase_add_test(tc, damaged_entries_are_discarded_and_rebuilt);
    tcase_add_test(tc, concurrent_processes_compile_once);
    tcase_add_test(tc, concurrent_threads_compile_once);
    tcase_add_test(tc, held_lock_is_waited_for_and_stale_one_is_not);
    tcase_add_test(tc, stale_temporary_files_are_removed);
    tcase_add_test(tc, off_writes_nothing);
    tcase_add_test(tc, entries_that_are_not_files_are_discarded);
    tcase_add_test(tc, slow_wall_time_alone_stores_nothing);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}

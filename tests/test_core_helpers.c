/* test_core_helpers.c - the library-internal helpers of src/core: the growable array
 * (pg_array.h) grows by doubling, keeps its contents, refuses sizes that would wrap
 * around size_t instead of allocating a small block, and leaves the array untouched on
 * refusal; the 3-vector helpers (pg_vec3.h) satisfy the identities of the algebra and
 * compute exactly the expressions they replaced; a reserved span (pg_span.h) and a
 * planet of some rows (pg_planet_alloc_rows) commit only the opened rows, which read
 * as zero, and a touch of any other row faults; the image quantiser's rounding
 * (pg_quantise.h) is lround on every float of 0..1 scaled to 8 and 16 bits; the huge-page
 * allocators (pg_huge.h) align big blocks to 2 MB, zero what pg_huge_calloc returns even
 * where the allocator hands back dirty memory, refuse sizes that wrap around size_t, and
 * touch a big block in far fewer page faults than 4 KB pages take. */
#include "pg_test.h"

#include "pg_array.h"
#include "pg_huge.h"
#include "pg_quantise.h"
#include "pg_span.h"
#include "pg_vec3.h"
#include "planetgen/pg_planet.h"

#include <signal.h>
#include <malloc.h>
#include <sys/resource.h>
#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static void test_array_growth(void **state) {
    (void)state;
    uint32_t *a = NULL;
    size_t n = 0, cap = 0, reallocs = 0;
    pg_error err = {0};
    for (uint32_t i = 0; i < 100000; i++) {
        size_t before = cap;
        assert_int_equal(PG_ARRAY_RESERVE(a, &cap, n + 1, &err), PG_OK);
        assert_true(cap >= n + 1);
        if (cap != before) {
            reallocs++;
            /* first capacity, then doubling */
            assert_true(before == 0 ? cap == PG_ARRAY_MIN_CAP : cap == 2 * before);
        }
        a[n++] = i * 7u;
    }
    for (uint32_t i = 0; i < n; i++)
        assert_int_equal(a[i], i * 7u);
    /* O(log n) reallocations: 16 * 2^13 = 131072 is the first capacity >= 100000 */
    assert_int_equal(cap, 131072);
    assert_int_equal(reallocs, 14);
    assert_int_equal(err.status, PG_OK);
    free(a);
}

static void test_array_reserve_jumps(void **state) {
    (void)state;
    double *a = NULL;
    size_t cap = 0;
    /* one call for many elements doubles until it fits, in one reallocation */
    assert_int_equal(PG_ARRAY_RESERVE(a, &cap, 1000, NULL), PG_OK);
    assert_int_equal(cap, 1024);
    a[999] = 1.5;
    /* enough room already: nothing changes */
    double *same = a;
    assert_int_equal(PG_ARRAY_RESERVE(a, &cap, 1024, NULL), PG_OK);
    assert_ptr_equal(a, same);
    assert_int_equal(cap, 1024);
    assert_int_equal(PG_ARRAY_RESERVE(a, &cap, 1025, NULL), PG_OK);
    assert_int_equal(cap, 2048);
    assert_true(a[999] == 1.5);
    free(a);
}

static void test_array_zero_sizes(void **state) {
    (void)state;
    int *a = NULL;
    size_t cap = 0;
    pg_error err = {0};
    /* room for no elements: nothing to allocate */
    assert_int_equal(PG_ARRAY_RESERVE(a, &cap, 0, &err), PG_OK);
    assert_null(a);
    assert_int_equal(cap, 0);
    /* a zero element size is a caller error, not a division by zero */
    assert_int_equal(pg_array_reserve(&a, &cap, 4, 0, &err), PG_ERR_BADINPUT);
    assert_int_equal(err.status, PG_ERR_BADINPUT);
    assert_null(a);
    assert_int_equal(cap, 0);
}

static void test_array_overflow_refused(void **state) {
    (void)state;
    uint64_t *a = NULL;
    size_t cap = 0;
    pg_error err = {0};
    assert_int_equal(PG_ARRAY_RESERVE(a, &cap, 100, &err), PG_OK);
    a[0] = 42;
    uint64_t *kept = a;
    /* need * 8 wraps around size_t: refused, array untouched */
    const size_t huge[] = {SIZE_MAX, SIZE_MAX / 8 + 1, SIZE_MAX / 2};
    for (size_t k = 0; k < sizeof huge / sizeof huge[0]; k++) {
        pg_error_clear(&err);
        assert_int_equal(PG_ARRAY_RESERVE(a, &cap, huge[k], &err), PG_ERR_NOMEM);
        assert_int_equal(err.status, PG_ERR_NOMEM);
        assert_true(strlen(err.msg) > 0);
        assert_ptr_equal(a, kept);
        assert_int_equal(cap, 128);
        assert_int_equal(a[0], 42);
    }
    /* the same with a large element size and a modest count */
    pg_error_clear(&err);
    assert_int_equal(pg_array_reserve(&a, &cap, 1u << 20, SIZE_MAX / 1024, &err), PG_ERR_NOMEM);
    assert_ptr_equal(a, kept);
    assert_int_equal(cap, 128);
    /* err may be NULL: the status alone reports the refusal */
    assert_int_equal(PG_ARRAY_RESERVE(a, &cap, SIZE_MAX, NULL), PG_ERR_NOMEM);
    free(a);
}

static void test_vec3_arithmetic(void **state) {
    (void)state;
    const double a[3] = {1.5, -2.25, 4}, b[3] = {0.5, 3, -1};
    double o[3];
    pg_vec3_add(a, b, o);
    assert_true(o[0] == 2 && o[1] == 0.75 && o[2] == 3);
    pg_vec3_sub(a, b, o);
    assert_true(o[0] == 1 && o[1] == -5.25 && o[2] == 5);
    pg_vec3_scale(a, -2, o);
    assert_true(o[0] == -3 && o[1] == 4.5 && o[2] == -8);
    assert_true(pg_vec3_dot(a, b) == 0.75 - 6.75 - 4);
    /* in place: o may alias an input */
    double v[3] = {1, 2, 3};
    pg_vec3_add(v, v, v);
    assert_true(v[0] == 2 && v[1] == 4 && v[2] == 6);
    pg_vec3_sub(v, b, v);
    assert_true(v[0] == 1.5 && v[1] == 1 && v[2] == 7);
}

static void test_vec3_cross(void **state) {
    (void)state;
    const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    double o[3];
    pg_vec3_cross(x, y, o);
    assert_true(o[0] == 0 && o[1] == 0 && o[2] == 1);
    pg_vec3_cross(y, z, o);
    assert_true(o[0] == 1 && o[1] == 0 && o[2] == 0);
    pg_vec3_cross(z, x, o);
    assert_true(o[0] == 0 && o[1] == 1 && o[2] == 0);
    /* orthogonal to both factors, antisymmetric, |a x b|^2 = |a|^2 |b|^2 - (a.b)^2 */
    uint32_t s = 12345;
    for (int t = 0; t < 1000; t++) {
        double a[3], b[3], ab[3], ba[3];
        for (int k = 0; k < 3; k++) {
            s = s * 1664525u + 1013904223u;
            a[k] = (double)s / 4294967296.0 * 2 - 1;
            s = s * 1664525u + 1013904223u;
            b[k] = (double)s / 4294967296.0 * 2 - 1;
        }
        pg_vec3_cross(a, b, ab);
        pg_vec3_cross(b, a, ba);
        assert_true(fabs(pg_vec3_dot(ab, a)) < 1e-15);
        assert_true(fabs(pg_vec3_dot(ab, b)) < 1e-15);
        for (int k = 0; k < 3; k++)
            assert_true(ab[k] == -ba[k]);
        double lagrange =
            pg_vec3_dot(a, a) * pg_vec3_dot(b, b) - pg_vec3_dot(a, b) * pg_vec3_dot(a, b);
        assert_true(fabs(pg_vec3_dot(ab, ab) - lagrange) < 1e-14);
    }
    double self[3];
    pg_vec3_cross(x, x, self);
    assert_true(self[0] == 0 && self[1] == 0 && self[2] == 0);
}

static void test_vec3_length_normalize(void **state) {
    (void)state;
    const double p[3] = {3, 4, 12};
    assert_true(pg_vec3_length(p) == 13);
    double v[3] = {3, 4, 12};
    pg_vec3_normalize(v);
    assert_true(v[0] == 3.0 / 13 && v[1] == 4.0 / 13 && v[2] == 12.0 / 13);
    assert_true(fabs(pg_vec3_length(v) - 1) < 1e-15);
    /* the same bits as the expression it replaced: each component divided by the length */
    double w[3] = {0.1, -0.7, 2.3}, r[3] = {0.1, -0.7, 2.3};
    double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    r[0] /= len, r[1] /= len, r[2] /= len;
    pg_vec3_normalize(w);
    assert_memory_equal(w, r, sizeof w);
    /* tiny and huge vectors keep their direction and come out unit length */
    double tiny[3] = {1e-100, 0, -1e-100}, huge[3] = {1e150, 1e150, 0};
    pg_vec3_normalize(tiny);
    pg_vec3_normalize(huge);
    assert_true(fabs(pg_vec3_length(tiny) - 1) < 1e-15);
    assert_true(fabs(pg_vec3_length(huge) - 1) < 1e-15);
    assert_true(tiny[0] > 0 && tiny[1] == 0 && tiny[2] < 0);
    /* the zero vector stays zero instead of turning into NaNs */
    double zero[3] = {0, 0, 0};
    pg_vec3_normalize(zero);
    assert_true(zero[0] == 0 && zero[1] == 0 && zero[2] == 0);
}

/* Touch *p in a child process: 1 when the child died of the touch (a fault; under
 * ASan, its report and exit 1), 0 when it wrote and read the value back. */
static int touch_faults(volatile float *p) {
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        signal(SIGSEGV, SIG_DFL); /* not cmocka's handler, which would go on in the child */
        signal(SIGBUS, SIG_DFL);
        *p = 1.5f;
        _exit(*p == 1.5f ? 0 : 3);
    }
    int st = 0;
    assert_true(pid > 0 && waitpid(pid, &st, 0) == pid);
    if (WIFEXITED(st) && WEXITSTATUS(st) == 0) return 0;
    return (WIFSIGNALED(st) && WTERMSIG(st) == SIGSEGV) || (WIFEXITED(st) && WEXITSTATUS(st) == 1);
}

/* under valgrind a deliberate fault counts as an error of the run: skip that part */
static int under_valgrind(void) {
    const char *p = getenv("LD_PRELOAD");
    return p && strstr(p, "vgpreload");
}

static void test_span_opens_only_its_rows(void **state) {
    (void)state;
    pg_error err = {0};
    pg_span s;
    const size_t row = 1 << 16, rows = 64; /* 4 MB */
    assert_int_equal(pg_span_reserve(&s, rows * row, &err), PG_OK);
    assert_non_null(s.base);
    assert_int_equal(pg_span_open(&s, 10 * row, 5 * row, &err), PG_OK);
    float *f = s.base;
    const size_t per = row / sizeof(float);
    for (size_t i = 10 * per; i < 15 * per; i++)
        assert_true(f[i] == 0.0f), f[i] = (float)i;
    assert_true(f[12 * per + 7] == (float)(12 * per + 7));
    /* opening again (overlapping) keeps what was written */
    assert_int_equal(pg_span_open(&s, 12 * row, 10 * row, &err), PG_OK);
    assert_true(f[12 * per + 7] == (float)(12 * per + 7));
    assert_true(f[21 * per] == 0.0f);
    if (!under_valgrind()) {
        assert_int_equal(touch_faults(&f[11 * per]), 0);
        assert_int_equal(touch_faults(&f[9 * per]), 1);  /* below the opened rows */
        assert_int_equal(touch_faults(&f[40 * per]), 1); /* above */
    }
    pg_span_free(&s);
    assert_null(s.base);
    pg_span_free(&s); /* safe twice */
}

static void test_planet_alloc_rows(void **state) {
    (void)state;
    pg_error err = {0};
    pg_planet p;
    const int64_t y0[6] = {0, 0, 24, 0, 0, 0}, y1[6] = {0, 0, 40, 64, 0, 0};
    assert_int_equal(pg_planet_alloc_rows(&p, PG_CUBE_DEFAULT_PROJECTION, 4, 16,
                                          pg_ellipsoid_sphere(), y0, y1, &err),
                     PG_OK);
    assert_int_equal(p.n, 64);
    for (int f = 2; f <= 3; f++)
        for (int64_t y = y0[f]; y < y1[f]; y++)
            for (int64_t x = 0; x < 64; x++) {
                assert_true(p.height[f][y * 64 + x] == 0.0f);
                p.height[f][y * 64 + x] = (float)y;
                p.albedo[f][(y * 64 + x) * 3 + 2] = 0.5f;
            }
    assert_true(p.height[3][63 * 64 + 63] == 63.0f);
    if (!under_valgrind()) {
        /* rows far from the open ones, beyond any page rounding (a row is 256 B) */
        assert_int_equal(touch_faults(&p.height[2][0]), 1);
        assert_int_equal(touch_faults(&p.albedo[2][0]), 1);
        assert_int_equal(touch_faults(&p.height[0][32 * 64]), 1);
        assert_int_equal(touch_faults(&p.height[3][5]), 0);
    }
    /* and the whole planet on demand: old rows kept, new rows zero */
    assert_int_equal(pg_planet_open_all_rows(&p, &err), PG_OK);
    assert_true(p.height[2][30 * 64] == 30.0f && p.height[0][32 * 64] == 0.0f);
    if (!under_valgrind()) assert_int_equal(touch_faults(&p.height[0][32 * 64]), 0);
    pg_planet_free(&p);
    assert_null(p.height[2]);
}

/* pg_round_half_up against lround: every 61st float of [0, 1] (all of them take a minute)
 * times 255 and 65535, every tie k + 1/2 of 16 bits and its two neighbours, and the
 * float just below 1/2, whose sum with 1/2 rounds up to 1 in double. */
static void test_round_half_up(void **s) {
    (void)s;
    uint64_t checked = 0;
    for (uint32_t b = 0; b <= 0x3f800000u; b += 61) {
        float v;
        memcpy(&v, &b, sizeof v);
        const double scale[2] = {255.0, 65535.0};
        for (int k = 0; k < 2; k++, checked++) {
            double x = v * scale[k];
            if (pg_round_half_up(x) != (double)lround(x)) fail_msg("%.17g", x);
        }
    }
    for (int k = 0; k <= 65535; k++) {
        const double t = k + 0.5, x[3] = {t, nextafter(t, 0), nextafter(t, 1e9)};
        for (int i = 0; i < 3; i++, checked++)
            if (pg_round_half_up(x[i]) != (double)lround(x[i])) fail_msg("%.17g", x[i]);
    }
    assert_true(pg_round_half_up(0.5) == 1 && pg_round_half_up(2.5) == 3);
    assert_true(pg_round_half_up(nextafter(0.5, 0)) == 0);
    printf("pg_round_half_up: %llu values as lround\n", (unsigned long long)checked);
}

/* Whether transparent huge pages are given on request only ("madvise"), so that a plain
 * block keeps 4 KB pages and a pg_huge block gets 2 MB ones. */
static int thp_on_request(void) {
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (!f) return 0;
    char line[128] = {0};
    int ok = fgets(line, sizeof line, f) && strstr(line, "[madvise]");
    fclose(f);
    return ok;
}

/* The kB of the mapping that holds p backed by transparent huge pages (/proc/self/smaps'
 * AnonHugePages); 0 when it cannot be read. */
static long anon_huge_kb(const void *p) {
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f) return 0;
    char line[512];
    int inside = 0;
    long kb = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' '))
            inside = (uintptr_t)p >= lo && (uintptr_t)p < hi;
        else if (inside && sscanf(line, "AnonHugePages: %ld kB", &kb) == 1)
            break;
    }
    fclose(f);
    return inside ? kb : 0;
}

static long minor_faults(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_minflt;
}

static void test_huge_alloc(void **state) {
    (void)state;
    const size_t big = (size_t)64 << 20, huge = (size_t)2 << 20;
    /* big blocks are aligned to whole huge pages; small ones are plain malloc blocks */
    unsigned char *p = pg_huge_malloc(big);
    assert_non_null(p);
    assert_int_equal((uintptr_t)p % huge, 0);
    void *q = pg_huge_malloc(100);
    assert_non_null(q);
    free(q);
    /* touching a big block faults once per 2 MB page, not once per 4 KB page as a plain
     * block of the same size does (compared with one, since sanitizers add their own
     * faults for their shadow memory) */
    unsigned char *plain = malloc(big);
    assert_non_null(plain);
    long f0 = minor_faults();
    memset(plain, 0xab, big);
    long f1 = minor_faults();
    memset(p, 0xab, big);
    long f2 = minor_faults();
    const long hp_kb = anon_huge_kb(p);
    print_message("64 MB touched in %ld minor faults (a plain block: %ld); %ld kB of it on "
                  "huge pages\n",
                  f2 - f1, f1 - f0, hp_kb);
    /* asserted where the kernel gave the block huge pages (it may not: fragmented
     * memory, THP off) and only them on request, so that the plain block has 4 KB ones */
    if (thp_on_request() && hp_kb >= (long)(big >> 11)) assert_true(4 * (f2 - f1) <= f1 - f0);
    free(plain);
    free(p);
    /* pg_huge_calloc zeroes, also where the block it gets was written before: with the
     * mmap threshold above the block and no trimming, a freed block stays in the heap
     * and the next one of its size is carved from it (sanitizers keep their own
     * allocators: there the second block is fresh) */
    const size_t mid = (size_t)16 << 20;
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    unsigned char *first = NULL;
    for (int round = 0; round < 2; round++) {
        unsigned char *z = pg_huge_calloc(mid / 8, 8);
        assert_non_null(z);
        size_t nonzero = 0;
        for (size_t i = 0; i < mid; i++)
            nonzero += z[i] != 0;
        assert_int_equal(nonzero, 0);
        if (round == 1)
            print_message("the second block %s the first\n", z == first ? "reuses" : "is not");
        first = z;
        memset(z, 0xcd, mid);
        __asm__ volatile("" : : "r"(z) : "memory"); /* the writes happen before free */
        free(z);
    }
    mallopt(M_MMAP_THRESHOLD, 128 << 10);
    mallopt(M_TRIM_THRESHOLD, 128 << 10);
    unsigned char *small = pg_huge_calloc(10, 10);
    assert_non_null(small);
    for (int i = 0; i < 100; i++)
        assert_int_equal(small[i], 0);
    free(small);
    /* a count times size that wraps around size_t is refused, not truncated */
    assert_null(pg_huge_calloc(SIZE_MAX / 2, 4));
    assert_null(pg_huge_alloc(SIZE_MAX - 100));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_array_growth),
        cmocka_unit_test(test_array_reserve_jumps),
        cmocka_unit_test(test_array_zero_sizes),
        cmocka_unit_test(test_array_overflow_refused),
        cmocka_unit_test(test_round_half_up),
        cmocka_unit_test(test_vec3_arithmetic),
        cmocka_unit_test(test_vec3_cross),
        cmocka_unit_test(test_vec3_length_normalize),
        cmocka_unit_test(test_span_opens_only_its_rows),
        cmocka_unit_test(test_planet_alloc_rows),
        cmocka_unit_test(test_huge_alloc),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

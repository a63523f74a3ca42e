/* fuzz_common.h - shared bits of planetgen's libFuzzer harnesses: a private scratch
 * directory per process and writing the fuzz input to a file there. The harnesses
 * are also built without libFuzzer (fuzz_driver.c) to replay the corpus under ctest. */
#ifndef PG_FUZZ_COMMON_H
#define PG_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Scratch directory /tmp/pg-fuzz-PID (created on first use) into buf. */
static inline const char *pg_fuzz_dir(char *buf, size_t size) {
    snprintf(buf, size, "/tmp/pg-fuzz-%d", (int)getpid());
    mkdir(buf, 0700);
    return buf;
}

static inline int pg_fuzz_write(const char *path, const uint8_t *data, size_t size) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t n = size ? fwrite(data, 1, size, f) : 0;
    fclose(f);
    return n == size ? 0 : -1;
}

#endif

/* fuzz_driver.c - replays a fuzz corpus through a harness without libFuzzer, so
 * ctest (with gcc, and under the sanitizer build) re-runs every saved input and
 * every past crash as a regression test. Usage: fuzz_X DIR_OR_FILE... */
#include "fuzz_common.h"

#include <dirent.h>
#include <string.h>

static int run_file(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *buf = malloc(n > 0 ? (size_t)n : 1);
    size_t got = buf ? fread(buf, 1, (size_t)n, f) : 0;
    fclose(f);
    if (!buf || got != (size_t)n) {
        free(buf);
        return -1;
    }
    LLVMFuzzerTestOneInput(buf, got);
    free(buf);
    return 0;
}

int main(int argc, char **argv) {
    int files = 0;
    for (int i = 1; i < argc; i++) {
        DIR *d = opendir(argv[i]);
        if (!d) {
            if (run_file(argv[i]) != 0) return 1;
            files++;
            continue;
        }
        struct dirent *e;
        while ((e = readdir(d))) {
            if (e->d_name[0] == '.') continue;
            char p[4096];
            snprintf(p, sizeof p, "%s/%s", argv[i], e->d_name);
            if (run_file(p) != 0) return 1;
            files++;
        }
        closedir(d);
    }
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf /tmp/pg-fuzz-%d", (int)getpid());
    if (system(cmd) != 0) return 1;
    printf("%d passed, 0 failed\n", files);
    return files > 0 ? 0 : 1;
}

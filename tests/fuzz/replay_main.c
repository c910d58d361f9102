/* SPDX-License-Identifier: MIT */
/**
 * @file replay_main.c
 * @brief main() for a harness built without libFuzzer (e.g. with gcc and
 * ASan/UBSan): runs LLVMFuzzerTestOneInput once per file named on the
 * command line (directories are read one level deep). Exit 0 when every
 * input ran; a contract violation aborts.
 */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static unsigned char buf[1u << 20];

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    size_t n;
    if (f == NULL) {
        (void)fprintf(stderr, "replay: cannot open %s\n", path);
        return 1;
    }
    n = fread(buf, 1u, sizeof buf, f);
    (void)fclose(f);
    (void)LLVMFuzzerTestOneInput(buf, n);
    return 0;
}

int main(int argc, char **argv)
{
    int i, bad = 0;
    unsigned long runs = 0u;
    for (i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            (void)fprintf(stderr, "replay: no such file %s\n", argv[i]);
            bad = 1;
            continue;
        }
        if (S_ISDIR(st.st_mode)) {
            DIR *d = opendir(argv[i]);
            struct dirent *e;
            if (d == NULL) {
                bad = 1;
                continue;
            }
            while ((e = readdir(d)) != NULL) {
                char path[4096];
                struct stat fst;
                if (e->d_name[0] == '.') {
                    continue;
                }
                (void)snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
                if (stat(path, &fst) == 0 && S_ISREG(fst.st_mode)) {
                    bad |= run_file(path);
                    runs++;
                }
            }
            (void)closedir(d);
        } else {
            bad |= run_file(argv[i]);
            runs++;
        }
    }
    (void)printf("replay: %lu inputs, no contract violation\n", runs);
    return bad;
}

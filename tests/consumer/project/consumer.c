/* Uses the installed C ABI: version, a sequence over caller memory, the copy filter. */
#include <stdio.h>
#include <statfilter/statfilter.h>

int main(void) {
    float in[2 * 2 * 3 * 1], out[2 * 2 * 3 * 1];
    sf_shape shape = {2, 2, 3, 1};
    sf_strides strides = {4, 4, 12, 24};
    sf_sequence a = NULL, b = NULL;
    sf_filter copy = NULL;
    int i;
    for (i = 0; i < 12; ++i) { in[i] = (float)i * 0.5f; out[i] = -1.0f; }
    if (sf_version() / 10000 != SF_VERSION_MAJOR) { fprintf(stderr, "version mismatch\n"); return 1; }
    if (sf_sequence_wrap(in, shape, strides, &a) != SF_OK || sf_sequence_wrap(out, shape, strides, &b) != SF_OK ||
        sf_filter_create("copy", &copy) != SF_OK || sf_filter_execute(copy, a, b) != SF_OK) {
        fprintf(stderr, "statfilter failed: %s\n", sf_last_error());
        return 1;
    }
    for (i = 0; i < 12; ++i)
        if (out[i] != in[i]) { fprintf(stderr, "sample %d differs\n", i); return 1; }
    sf_filter_release(copy);
    sf_sequence_release(a);
    sf_sequence_release(b);
    printf("consumer OK with statfilter %s\n", sf_version_string());
    return 0;
}

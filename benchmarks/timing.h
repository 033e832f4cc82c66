/* The timing both benchmark drivers share (bench.c, multibody_bench.c): included after the
 * driver defines its bench_data, which holds at least `int repeats` (samples per timing,
 * at most MAX_REPEATS) and `double min_seconds` (the shortest sample). */
#ifndef BENCH_TIMING_H
#define BENCH_TIMING_H

#define MAX_REPEATS 64

/* One pass over every input; returns a checksum so that the work cannot be dropped. */
typedef double (*pass_fn)(const bench_data *d);

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int compare(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *x, int n)
{
    qsort(x, (size_t)n, sizeof *x, compare);
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

static double checksum = 0.0;

/* Median over d->repeats samples of ns per item. A first pass warms the caches and sizes
 * the samples: each runs whole passes for at least d->min_seconds, so short kernels are
 * not timed at the clock's resolution. */
static double ns_per_item(pass_fn pass, const bench_data *d, size_t items)
{
    double samples[MAX_REPEATS], start = now();
    long passes, k;
    int r;
    checksum += pass(d);
    passes = (long)ceil(d->min_seconds / fmax(now() - start, 1e-9));
    if (passes < 1) passes = 1;
    for (r = 0; r < d->repeats; ++r) {
        start = now();
        for (k = 0; k < passes; ++k) checksum += pass(d);
        samples[r] = (now() - start) * 1e9 / ((double)passes * (double)items);
    }
    return median(samples, d->repeats);
}

#endif

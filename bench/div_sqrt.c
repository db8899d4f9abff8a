/* Throughput and latency of the vector division and square root in double precision, at both
 * widths the batch kernels use (ymm: AVX2 kernels, zmm: AVX-512 kernels). The physics of a
 * contact step has several of each per contact (geometry, the project-rescale transport of each
 * spring, each spring's clip), and a SIMD kernel computes them in every lane whether or not the
 * lane slips. See docs/performance.md, "Where the time goes".
 *
 *   cc -O2 -march=native bench/div_sqrt.c -o /tmp/div_sqrt && /tmp/div_sqrt
 *
 * Needs a CPU with AVX-512 F (the zmm rows). Throughput: eight independent chains, ns per
 * instruction; latency: one chain, ns per instruction.
 */
#define _POSIX_C_SOURCE 199309L
#include <immintrin.h>
#include <stdio.h>
#include <time.h>

#define N 100000000L

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Keeps eight registers live so that the compiler neither merges nor drops the chains. */
#define KEEP8(a)                                                                              \
    __asm__ volatile("" : "+v"(a[0]), "+v"(a[1]), "+v"(a[2]), "+v"(a[3]), "+v"(a[4]),       \
                     "+v"(a[5]), "+v"(a[6]), "+v"(a[7]))

#define THROUGHPUT(T, set1, op, ...)                                                          \
    do {                                                                                      \
        T a[8];                                                                               \
        for (int k = 0; k < 8; k++) a[k] = set1(1.0 + k * 1e-9);                              \
        double t0 = now();                                                                    \
        for (long i = 0; i < N / 8; i++) {                                                    \
            for (int k = 0; k < 8; k++) a[k] = op(a[k] __VA_ARGS__);                          \
            KEEP8(a);                                                                         \
        }                                                                                     \
        ns = (now() - t0) / N * 1e9;                                                          \
    } while (0)

#define LATENCY(T, set1, op, ...)                                                             \
    do {                                                                                      \
        T x = set1(1.5);                                                                      \
        double t0 = now();                                                                    \
        for (long i = 0; i < N / 8; i++) {                                                    \
            x = op(x __VA_ARGS__);                                                            \
            __asm__ volatile("" : "+v"(x));                                                   \
        }                                                                                     \
        ns = (now() - t0) / (N / 8) * 1e9;                                                    \
    } while (0)

int main(void)
{
    double ns;
    const __m512d b8 = _mm512_set1_pd(1.0000001);
    const __m256d b4 = _mm256_set1_pd(1.0000001);
    printf("instruction        throughput (ns)  latency (ns)\n");
    THROUGHPUT(__m256d, _mm256_set1_pd, _mm256_div_pd, , b4);
    double t = ns;
    LATENCY(__m256d, _mm256_set1_pd, _mm256_div_pd, , b4);
    printf("vdivpd  ymm (4)    %6.2f           %6.2f\n", t, ns);
    THROUGHPUT(__m512d, _mm512_set1_pd, _mm512_div_pd, , b8);
    t = ns;
    LATENCY(__m512d, _mm512_set1_pd, _mm512_div_pd, , b8);
    printf("vdivpd  zmm (8)    %6.2f           %6.2f\n", t, ns);
    THROUGHPUT(__m256d, _mm256_set1_pd, _mm256_sqrt_pd);
    t = ns;
    LATENCY(__m256d, _mm256_set1_pd, _mm256_sqrt_pd);
    printf("vsqrtpd ymm (4)    %6.2f           %6.2f\n", t, ns);
    THROUGHPUT(__m512d, _mm512_set1_pd, _mm512_sqrt_pd);
    t = ns;
    LATENCY(__m512d, _mm512_set1_pd, _mm512_sqrt_pd);
    printf("vsqrtpd zmm (8)    %6.2f           %6.2f\n", t, ns);
    return 0;
}

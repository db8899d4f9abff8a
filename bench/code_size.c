/* How fast this core runs a loop as its body grows: the same mix of instructions (per
 * repetition, twelve zmm additions and multiplications on twelve independent registers and
 * twelve integer additions, so that no instruction waits long on another) in loop bodies of 4
 * to 64 KB. While the body fits the core's decoded-instruction (op) cache, the front end delivers
 * more instructions per cycle than the decoders can; past it, the rate falls to what the
 * decoders sustain. The batch kernels' hot code is a few thousand instructions, so this says how
 * close they are to that limit. See docs/performance.md, "Where the time goes".
 *
 *   cc -O2 bench/code_size.c -o /tmp/code_size && /tmp/code_size
 *
 * Needs x86-64 with AVX-512 F (the zmm instructions) and the GNU assembler (`.rept`). Prints,
 * per body size, the instructions in the body and the instructions per ns (best of 5 runs).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* One repetition: 24 instructions, 120 bytes (vaddpd/vmulpd zmm: 6 bytes; add $1, reg: 4). */
#define REP_BYTES 120
#define REP_INSTRUCTIONS 24
#define BODY                                                                                  \
    "vaddpd %%zmm13, %%zmm0, %%zmm0\n\tadd $1, %%r8\n\t"                                      \
    "vmulpd %%zmm12, %%zmm1, %%zmm1\n\tadd $1, %%r9\n\t"                                      \
    "vaddpd %%zmm13, %%zmm2, %%zmm2\n\tadd $1, %%r10\n\t"                                     \
    "vmulpd %%zmm12, %%zmm3, %%zmm3\n\tadd $1, %%r11\n\t"                                     \
    "vaddpd %%zmm13, %%zmm4, %%zmm4\n\tadd $1, %%rsi\n\t"                                     \
    "vmulpd %%zmm12, %%zmm5, %%zmm5\n\tadd $1, %%rdi\n\t"                                     \
    "vaddpd %%zmm13, %%zmm6, %%zmm6\n\tadd $1, %%r8\n\t"                                      \
    "vmulpd %%zmm12, %%zmm7, %%zmm7\n\tadd $1, %%r9\n\t"                                      \
    "vaddpd %%zmm13, %%zmm8, %%zmm8\n\tadd $1, %%r10\n\t"                                     \
    "vmulpd %%zmm12, %%zmm9, %%zmm9\n\tadd $1, %%r11\n\t"                                     \
    "vaddpd %%zmm13, %%zmm10, %%zmm10\n\tadd $1, %%rsi\n\t"                                   \
    "vmulpd %%zmm12, %%zmm11, %%zmm11\n\tadd $1, %%rdi\n\t"

/* A loop whose body is REPS repetitions, run `iters` times. */
#define LOOP(NAME, REPS)                                                                      \
    static void NAME(long iters)                                                              \
    {                                                                                         \
        /* Every register zero: no subnormal or NaN operand anywhere. */                     \
        __asm__ volatile(".irp r, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13\n\t"          \
                         "vxorpd %%zmm\\r, %%zmm\\r, %%zmm\\r\n\t"                             \
                         ".endr\n\t"                                                          \
                         ".p2align 6\n"                                                       \
                         "1:\n\t"                                                             \
                         ".rept " #REPS "\n\t" BODY ".endr\n\t"                               \
                         "dec %0\n\t"                                                         \
                         "jnz 1b\n\t"                                                         \
                         "vzeroupper"                                                         \
                         : "+r"(iters)                                                        \
                         :                                                                    \
                         : "r8", "r9", "r10", "r11", "rsi", "rdi", "xmm0", "xmm1", "xmm2",   \
                           "xmm3", "xmm4", "xmm5", "xmm6", "xmm7", "xmm8", "xmm9", "xmm10",  \
                           "xmm11", "xmm12", "xmm13", "cc");                                 \
    }

LOOP(body4k, 34)
LOOP(body8k, 68)
LOOP(body16k, 136)
LOOP(body20k, 170)
LOOP(body24k, 204)
LOOP(body28k, 238)
LOOP(body32k, 273)
LOOP(body48k, 409)
LOOP(body64k, 546)

static void run(const char *name, void (*loop)(long), long reps)
{
    const long instructions = reps * REP_INSTRUCTIONS + 2;
    const long iters = 400000000L / instructions;
    loop(iters / 10);
    double best = 1e300;
    for (int r = 0; r < 5; r++) {
        double t = now();
        loop(iters);
        t = now() - t;
        if (t < best)
            best = t;
    }
    printf("%-6s body %6ld bytes %6ld instructions: %5.1f instructions per ns\n", name,
           reps * REP_BYTES, instructions, (double)instructions * (double)iters / best * 1e-9);
}

int main(void)
{
    run("4 KB", body4k, 34);
    run("8 KB", body8k, 68);
    run("16 KB", body16k, 136);
    run("20 KB", body20k, 170);
    run("24 KB", body24k, 204);
    run("28 KB", body28k, 238);
    run("32 KB", body32k, 273);
    run("48 KB", body48k, 409);
    run("64 KB", body64k, 546);
    return 0;
}

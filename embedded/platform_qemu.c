/* The mps2-an386 side of platform.h, run under qemu-system-arm -icount shift=ICOUNT_SHIFT:
 * each instruction advances virtual time by 2^ICOUNT_SHIFT ns, and a CMSDK APB timer clocked at
 * the board's 25 MHz counts that time, so instructions = ticks * 40 ns / 2^ICOUNT_SHIFT ns
 * (exact with ICOUNT_SHIFT >= 6, where one instruction lasts longer than one tick). The stack
 * is painted below the caller before, and searched for the deepest word changed after. */
#include <stddef.h>
#include <stdint.h>

#include "platform.h"

#ifndef ICOUNT_SHIFT
#error "ICOUNT_SHIFT: the -icount shift QEMU runs with (the Makefile passes both)"
#endif

#define TIMER0_CTRL (*(volatile uint32_t *)0x40000000u)   /* bit 0: enable */
#define TIMER0_VALUE (*(volatile uint32_t *)0x40000004u)  /* counts down */
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)
#define TIMER_TICK_NS 40u                                 /* 25 MHz */
#define PAINT 0xC0DEFACEu

extern uint32_t __stack_limit[];
extern char end[], __heap_end[];

static uint32_t start_ticks;
static uintptr_t start_sp;
static int calibrated = 0;
static unsigned long overhead = 0;   /* instructions of an empty measurement */

static uintptr_t stack_pointer(void)
{
    uintptr_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

static unsigned long instructions_between(uint32_t from, uint32_t to)
{
    const uint64_t ns = (uint64_t)(uint32_t)(from - to) * TIMER_TICK_NS;
    return (unsigned long)((ns + (1u << ICOUNT_SHIFT) / 2) >> ICOUNT_SHIFT);
}

static void start(void)
{
    start_sp = stack_pointer();
    for (uint32_t *word = __stack_limit; (uintptr_t)(word + 16) < start_sp; ++word) {
        *word = PAINT;
    }
    if (!(TIMER0_CTRL & 1u)) {
        TIMER0_RELOAD = 0xFFFFFFFFu;
        TIMER0_VALUE = 0xFFFFFFFFu;
        TIMER0_CTRL = 1u;
    }
    start_ticks = TIMER0_VALUE;
}

static void stop(measurement *result)
{
    const uint32_t ticks = TIMER0_VALUE;
    const uint32_t *word = __stack_limit;
    while (*word == PAINT && (uintptr_t)word < start_sp) {
        ++word;
    }
    result->measured = 1;
    result->instructions = instructions_between(start_ticks, ticks);
    result->stack_bytes = (unsigned long)(start_sp - (uintptr_t)word);
}

void measure_begin(void)
{
    if (!calibrated) {   /* once: what measuring nothing costs, called as a caller calls */
        measurement empty;
        calibrated = 1;
        measure_begin();
        measure_end(&empty);
        overhead = empty.instructions;
    }
    start();
}

void measure_end(measurement *result)
{
    stop(result);
    result->instructions -= overhead;
}

unsigned long platform_calibration(void)
{
    measurement loop;
    measure_begin();
    /* 1 + 2 x 1000 instructions */
    __asm__ volatile("mov r0, #1000\n1:\n\tsubs r0, r0, #1\n\tbne 1b" ::: "r0", "cc");
    measure_end(&loop);
    return loop.instructions;
}

/* Semihosting (ARM's debug monitor interface, which QEMU implements): operation in r0,
 * argument in r1, "bkpt 0xab" on M-profile. */
static uint32_t semihosting(uint32_t operation, uintptr_t argument)
{
    register uint32_t r0 __asm__("r0") = operation;
    register uintptr_t r1 __asm__("r1") = argument;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

#define SYS_WRITE0 0x04u
#define SYS_EXIT 0x18u
#define ADP_STOPPED_RUN_TIME_ERROR 0x20023u   /* QEMU exits with status 1 */

void platform_fail(const char *message)
{
    semihosting(SYS_WRITE0, (uintptr_t)message);
    semihosting(SYS_WRITE0, (uintptr_t)"\n");
    semihosting(SYS_EXIT, ADP_STOPPED_RUN_TIME_ERROR);
    for (;;) {
    }
}

/* newlib's malloc (stdio's buffers) takes memory from here: between the end of .bss and the
 * end of RAM (rdimon's own _sbrk wants the heap below the stack, which here is above it). */
void *_sbrk(ptrdiff_t increment);
void *_sbrk(ptrdiff_t increment)
{
    static char *top = end;
    if (increment > __heap_end - top) {
        return (void *)-1;
    }
    char *previous = top;
    top += increment;
    return previous;
}

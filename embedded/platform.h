/* What the test firmware's main needs from where it runs: QEMU's mps2-an386 (platform_qemu.c)
 * or the host (platform_host.c, the reference the firmware's output is compared with). */
#ifndef PLATFORM_H
#define PLATFORM_H

typedef struct measurement {
    int measured;                /* 0 on the host: nothing below is known there */
    unsigned long instructions;  /* executed between measure_begin and measure_end */
    unsigned long stack_bytes;   /* deepest stack use below measure_begin's caller */
} measurement;

/* Around the code to measure: the counts exclude measure_begin and measure_end themselves. */
void measure_begin(void);
void measure_end(measurement *result);

/* The instructions measured around a loop of exactly 2001 (0 where nothing is measured):
 * how exact the counts are. */
unsigned long platform_calibration(void);

/* Print the message and stop with a failure status. */
void platform_fail(const char *message) __attribute__((noreturn));

#endif /* PLATFORM_H */

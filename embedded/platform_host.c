/* The host side of platform.h: nothing is measured; the firmware's main runs as a program. */
#include <stdio.h>
#include <stdlib.h>

#include "platform.h"

void measure_begin(void)
{
}

void measure_end(measurement *result)
{
    result->measured = 0;
    result->instructions = 0;
    result->stack_bytes = 0;
}

unsigned long platform_calibration(void)
{
    return 0;
}

void platform_fail(const char *message)
{
    fprintf(stderr, "%s\n", message);
    exit(1);
}

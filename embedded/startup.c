/* Start-up of the test firmware on a Cortex-M4F (QEMU's mps2-an386): the vector table, and a
 * reset handler that copies .data from flash, zeroes .bss, turns the FPU on and runs main.
 * No vendor code: the addresses are the architecture's (ARMv7-M) and the linker script's. */
#include <stdint.h>
#include <stdlib.h>

#include "platform.h"

extern uint32_t __data_load[], __data_start[], __data_end[], __bss_start[], __bss_end[];
extern uint32_t __stack_top[];

int main(void);
void initialise_monitor_handles(void);   /* newlib's rdimon: semihosting stdio */
void reset_handler(void);
void fault_handler(void);

#define CPACR (*(volatile uint32_t *)0xE000ED88u)   /* coprocessor access control */
#define CP10_CP11_FULL_ACCESS (0xFu << 20)

void reset_handler(void)
{
    const uint32_t *from = __data_load;
    for (uint32_t *to = __data_start; to < __data_end; ++to) {
        *to = *from++;
    }
    for (uint32_t *to = __bss_start; to < __bss_end; ++to) {
        *to = 0;
    }
    /* Before any floating-point instruction: with the FPU off (its reset state) the first
     * one is a UsageFault. The hard-float code may use it from the first C statement on. */
    CPACR |= CP10_CP11_FULL_ACCESS;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    initialise_monitor_handles();
    exit(main());
}

/* newlib's exit runs _fini (and __libc_init_array _init), which the C runtime's crti.o would
 * bring; this firmware links no start files and has nothing to run there. */
void _init(void);
void _fini(void);
void _init(void)
{
}
void _fini(void)
{
}

/* Every fault and unexpected interrupt: say so and stop QEMU with a failure status. */
void fault_handler(void)
{
    platform_fail("fault: an exception the firmware does not handle");
}

typedef void (*vector)(void);

/* ARMv7-M: the initial stack pointer, then reset, NMI, HardFault, MemManage, BusFault,
 * UsageFault, 4 reserved, SVCall, DebugMonitor, reserved, PendSV, SysTick. */
__attribute__((section(".vectors"), used)) static const vector vectors[16] = {
    (vector)(uintptr_t)__stack_top, reset_handler, fault_handler, fault_handler,
    fault_handler, fault_handler, fault_handler, 0, 0, 0, 0, fault_handler, fault_handler, 0,
    fault_handler, fault_handler,
};

/* Cortex-M7 start-up for a bare-metal capture step: the vector table, .data and .bss, the FPU on, main. */
#include <stdint.h>
#include <stdlib.h>

extern uint32_t __stack_top, __data_load, __data_start, __data_end, __bss_start, __bss_end;
extern int main(void);
extern void initialise_monitor_handles(void);

void Reset_Handler(void) {
  uint32_t *src = &__data_load, *dst = &__data_start;
  while (dst < &__data_end) *dst++ = *src++;
  for (dst = &__bss_start; dst < &__bss_end;) *dst++ = 0;
  *(volatile uint32_t *) 0xE000ED88 |= 0xFu << 20;          /* CPACR: CP10 and CP11, the FPU, full access */
  __asm volatile ("dsb\n isb");
  initialise_monitor_handles();                             /* semihosting: stdout, stderr, exit */
  exit(main());
}

static void Fault_Handler(void) { exit(3); }

__attribute__((section(".vectors"), used)) static const void *const vectors[16] = {
  &__stack_top, (void *) Reset_Handler, (void *) Fault_Handler, (void *) Fault_Handler, (void *) Fault_Handler,
  (void *) Fault_Handler, (void *) Fault_Handler};

/* SPDX-License-Identifier: MIT */
/**
 * @file startup.c
 * @brief Boot stub for running sfit test programs on QEMU's mps2-an386
 * (Cortex-M4F) with semihosting; also mps2-an505 (Cortex-M33, secure state)
 * and mps2-an385 (Cortex-M3, no FPU).
 *
 * Reset: enable the FPU (CPACR) when compiled for one (__ARM_FP), enable
 * the separate MemManage/BusFault/UsageFault exceptions, then jump to
 * newlib's rdimon crt0 `_start`, which zeroes .bss, asks the host for argc/argv and the stack/heap (semihosting
 * HEAPINFO), runs the init arrays, calls main() and exit(main's result).
 * .data needs no copy: VMA == LMA in RAM and QEMU's ELF loader writes it.
 *
 * Every other exception (faults, NMI, SVC, SysTick, IRQs) lands in one
 * handler that prints the exception number, stacked PC/LR and fault status
 * registers to the semihosting console and exits QEMU with status
 * 100 + exception number (HardFault 103, MemManage 104, BusFault 105,
 * UsageFault 106), so a crashing test fails fast instead of hanging.
 * Nothing here touches a float register before the FPU is on.
 */
#include <stdint.h>

/* System control block registers used here (ARMv7-M ARM, B3.2). */
#define PRV_REG(addr) (*(volatile uint32_t *)(addr))
#define PRV_SCB_SHCSR PRV_REG(0xE000ED24u) /* bits 16..18: enable MEM/BUS/USG faults */
#define PRV_SCB_CFSR PRV_REG(0xE000ED28u)  /* configurable fault status */
#define PRV_SCB_HFSR PRV_REG(0xE000ED2Cu)  /* hard fault status */
#define PRV_SCB_MMFAR PRV_REG(0xE000ED34u) /* MemManage fault address */
#define PRV_SCB_BFAR PRV_REG(0xE000ED38u)  /* BusFault address */
#define PRV_SCB_CPACR PRV_REG(0xE000ED88u) /* bits 20..23: CP10/CP11 access */

/* Semihosting operations and the "application exit" reason code. */
#define PRV_SYS_WRITE0 0x04u
#define PRV_SYS_EXIT 0x18u
#define PRV_SYS_EXIT_EXTENDED 0x20u
#define PRV_ADP_APPLICATION_EXIT 0x20026u
#define PRV_ADP_RUNTIME_ERROR 0x20023u

#define PRV_NUM_IRQ 32 /* external interrupts wired on QEMU's mps2-an386 */

extern unsigned char __stack[];               /* linker script: initial MSP */
extern void _start(void) __attribute__((noreturn)); /* newlib rdimon crt0 */

void Reset_Handler(void) __attribute__((noreturn));
void Default_Handler(void) __attribute__((naked, noreturn));
void sfit_m4f_fault_report(const uint32_t *frame, uint32_t exc_return)
    __attribute__((noreturn, used));

/** @brief One semihosting call (BKPT 0xAB); returns the host's r0. */
static uint32_t prv_semihost(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void Reset_Handler(void)
{
#if defined(__ARM_FP)
    PRV_SCB_CPACR |= 0xFu << 20; /* full access to CP10/CP11 (the FPU) */
#endif
    PRV_SCB_SHCSR |= 0x7u << 16; /* report MemManage/BusFault/UsageFault apart */
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    _start();
}

/** @brief Append "0x%08x" of v to *p. */
static void prv_put_hex(char **p, uint32_t v)
{
    int shift;
    *(*p)++ = '0';
    *(*p)++ = 'x';
    for (shift = 28; shift >= 0; shift -= 4) {
        *(*p)++ = "0123456789abcdef"[(v >> (unsigned)shift) & 0xFu];
    }
}

static void prv_put_str(char **p, const char *s)
{
    while (*s != '\0') {
        *(*p)++ = *s++;
    }
}

/*
 * Default_Handler: pick the stack the exception frame was pushed on (EXC_RETURN
 * bit 2) and hand it to the C reporter. Naked so nothing is pushed first.
 */
void Default_Handler(void)
{
    __asm__ volatile("tst   lr, #4\n\t"
                     "ite   eq\n\t"
                     "mrseq r0, msp\n\t"
                     "mrsne r0, psp\n\t"
                     "mov   r1, lr\n\t"
                     "b     sfit_m4f_fault_report\n\t");
}

void sfit_m4f_fault_report(const uint32_t *frame, uint32_t exc_return)
{
    static char msg[160];
    uint32_t block[2];
    uint32_t ipsr;
    char *p = msg;

    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    ipsr &= 0x1FFu;
    prv_put_str(&p, "\nsfit-m4f: exception ");
    *p++ = (char)('0' + (ipsr / 100u) % 10u);
    *p++ = (char)('0' + (ipsr / 10u) % 10u);
    *p++ = (char)('0' + ipsr % 10u);
    prv_put_str(&p, " pc=");
    prv_put_hex(&p, frame[6]); /* stacked r0-r3, r12, lr, pc, xpsr */
    prv_put_str(&p, " lr=");
    prv_put_hex(&p, frame[5]);
    prv_put_str(&p, " cfsr=");
    prv_put_hex(&p, PRV_SCB_CFSR);
    prv_put_str(&p, " hfsr=");
    prv_put_hex(&p, PRV_SCB_HFSR);
    prv_put_str(&p, " mmfar=");
    prv_put_hex(&p, PRV_SCB_MMFAR);
    prv_put_str(&p, " bfar=");
    prv_put_hex(&p, PRV_SCB_BFAR);
    prv_put_str(&p, " exc_return=");
    prv_put_hex(&p, exc_return);
    prv_put_str(&p, "\n");
    *p = '\0';
    (void)prv_semihost(PRV_SYS_WRITE0, msg);

    /* Exit status 100 + exception number; SYS_EXIT_EXTENDED carries it. */
    block[0] = PRV_ADP_APPLICATION_EXIT;
    block[1] = 100u + (ipsr > 155u ? 155u : ipsr);
    (void)prv_semihost(PRV_SYS_EXIT_EXTENDED, block);
    /* Host without EXIT_EXTENDED: plain SYS_EXIT with an error reason (status 1). */
    (void)prv_semihost(PRV_SYS_EXIT, (const void *)PRV_ADP_RUNTIME_ERROR);
    for (;;) {
    }
}

/* ARMv7-M vector table: initial MSP, then exceptions 1..15, then IRQs. */
typedef void (*prv_handler_t)(void);
typedef struct {
    void *initial_sp;
    prv_handler_t handler[15 + PRV_NUM_IRQ];
} prv_vector_table_t;

#define PRV_D Default_Handler
#define PRV_D8 PRV_D, PRV_D, PRV_D, PRV_D, PRV_D, PRV_D, PRV_D, PRV_D

__attribute__((section(".isr_vector"), used)) static const prv_vector_table_t prv_vectors = {
    __stack,
    {
        Reset_Handler, /* 1 */
        PRV_D,         /* 2 NMI */
        PRV_D,         /* 3 HardFault */
        PRV_D,         /* 4 MemManage */
        PRV_D,         /* 5 BusFault */
        PRV_D,         /* 6 UsageFault */
        PRV_D, PRV_D, PRV_D, PRV_D, /* 7..10 reserved */
        PRV_D,         /* 11 SVCall */
        PRV_D,         /* 12 DebugMonitor */
        PRV_D,         /* 13 reserved */
        PRV_D,         /* 14 PendSV */
        PRV_D,         /* 15 SysTick */
        PRV_D8, PRV_D8, PRV_D8, PRV_D8, /* IRQ 0..31 */
    },
};

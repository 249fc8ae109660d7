/*
 * hal_f28335_sci.c - SCI-A at 115200 8N1, transmit only, fed from a ring
 * buffer by a background pump (no interrupt: the ISR never waits on it).
 * Reference: SPRUG03 sections "SCI Baud Rate", "SCI FIFO", register section.
 * Pins: GPIO29 = SCITXDA, GPIO28 = SCIRXDA (muxed for later use).
 *
 * Single producer (hal_f28335_sci_write) and single consumer (the pump):
 * each index is written by one side only, as one 16-bit store.
 */
#include "DSP2833x_Device.h"
#include "hal_f28335.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

F28335_STATIC_ASSERT(brr_fits_16_bits, F28335_SCI_BRR >= 1U && F28335_SCI_BRR <= 0xFFFFU);

#define SCICCR_8N1_ASYNC    0x0007U  /* SCICHAR = 7 (8 bits), 1 stop, no parity, idle-line */
#define SCICTL1_TX_RESET    0x0002U  /* TXENA, SWRESET = 0 (held in reset) */
#define SCICTL1_TX_RUN      0x0022U  /* TXENA, SWRESET = 1 */
#define SCIFFTX_FIFO_ON     0xE040U  /* SCIRST, SCIFFENA, TXFIFOXRESET, TXFFINTCLR */
#define GPIO_MUX_PERIPH1    1U
#define GPIO_QSEL_ASYNC     3U
#define SCI_RING_LEN        256U     /* power of two; one slot stays empty */
#define SCI_CHAR_MASK       0x00FFU

static char s_ring[SCI_RING_LEN];
static volatile uint16_t s_head;  /* next slot to fill: producer only */
static volatile uint16_t s_tail;  /* next slot to send: pump only */

void f28335_sci_init(void)
{
    s_head = 0U;
    s_tail = 0U;

    EALLOW;
    GpioCtrlRegs.GPAPUD.bit.GPIO28 = 0U;
    GpioCtrlRegs.GPAPUD.bit.GPIO29 = 0U;
    GpioCtrlRegs.GPAQSEL2.bit.GPIO28 = GPIO_QSEL_ASYNC;
    GpioCtrlRegs.GPAMUX2.bit.GPIO28 = GPIO_MUX_PERIPH1;
    GpioCtrlRegs.GPAMUX2.bit.GPIO29 = GPIO_MUX_PERIPH1;
    EDIS;

    SciaRegs.SCICCR.all = SCICCR_8N1_ASYNC;
    SciaRegs.SCICTL1.all = SCICTL1_TX_RESET;
    SciaRegs.SCICTL2.all = 0U;  /* no SCI interrupts */
    SciaRegs.SCIHBAUD = (Uint16)(F28335_SCI_BRR >> 8);
    SciaRegs.SCILBAUD = (Uint16)(F28335_SCI_BRR & 0x00FFU);
    SciaRegs.SCIFFTX.all = SCIFFTX_FIFO_ON;
    SciaRegs.SCIFFCT.all = 0U;  /* no delay between FIFO words */
    SciaRegs.SCICTL1.all = SCICTL1_TX_RUN;
}

uint16_t hal_f28335_sci_write(const char *data, uint16_t len)
{
    uint16_t head = s_head;
    uint16_t n = 0U;

    while (n < len) {
        const uint16_t next = (uint16_t)((head + 1U) & (SCI_RING_LEN - 1U));
        if (next == s_tail) {
            break;  /* full */
        }
        s_ring[head] = data[n];
        head = next;
        n++;
    }
    s_head = head;
    return n;
}

void hal_f28335_sci_pump(void)
{
    uint16_t tail = s_tail;
    uint16_t room = (uint16_t)(F28335_SCI_FIFO_DEPTH - SciaRegs.SCIFFTX.bit.TXFFST);

    while ((room > 0U) && (tail != s_head)) {
        SciaRegs.SCITXBUF = (Uint16)((Uint16)s_ring[tail] & SCI_CHAR_MASK);
        tail = (uint16_t)((tail + 1U) & (SCI_RING_LEN - 1U));
        room--;
    }
    s_tail = tail;
}

/*
 * hal_f28335_sci.c - SCI-A 8N1 for the link (firmware/link/link_protocol.md):
 * both FIFOs on, never waiting. Transmit: a ring buffer fed by the
 * background, moved into the 16-word FIFO by hal_f28335_sci_pump() or,
 * above F28335_SCI_TX_IRQ_MIN_BAUD (hal_f28335_cfg.h), by the transmit
 * FIFO interrupt (PIE INT9.2, SCITXINTA), which the pump then only
 * enables; the interrupt disables itself when the ring is empty.
 * Receive: hal_f28335_sci_read() takes what the FIFO holds (at most 16
 * words per call, so its cost is bounded); a word flagged with a framing
 * or parity error is dropped, a FIFO overflow and a receiver error (break,
 * overrun) are counted and cleared - the link's CRC and resync handle the
 * bytes lost. Baud from LSPCLK (hal_f28335_cfg.h: BRR and its error).
 * Reference: SPRUG03 sections "SCI Baud Rate", "SCI FIFO", registers.
 * Pins: GPIO29 = SCITXDA, GPIO28 = SCIRXDA.
 *
 * Single producer and single consumer per ring: each index is written by
 * one side only, as one 16-bit store (with the interrupt, s_tail only by
 * it). TXFFIENA is set by the background and cleared by the interrupt:
 * the interrupt cannot be interrupted by the background, and a background
 * read-modify-write of SCIFFTX that the interrupt cuts into writes
 * TXFFIENA = 1 after data was queued, so at worst one interrupt finds the
 * ring empty and clears it again.
 */
#include "DSP2833x_Device.h"
#include "hal_f28335.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

F28335_STATIC_ASSERT(brr_fits_16_bits, F28335_SCI_BRR >= 1U && F28335_SCI_BRR <= 0xFFFFU);
F28335_STATIC_ASSERT(baud_error_within_2_percent, F28335_SCI_ERROR_PER_10K <= F28335_SCI_ERROR_MAX_PER_10K &&
                                                  F28335_SCI_ERROR_PER_10K >= -F28335_SCI_ERROR_MAX_PER_10K);

#define SCICCR_8N1_ASYNC    0x0007U  /* SCICHAR = 7 (8 bits), 1 stop, no parity, idle-line */
#define SCICTL1_RESET       0x0003U  /* RXENA, TXENA, SWRESET = 0 (held in reset) */
#define SCICTL1_RUN         0x0023U  /* RXENA, TXENA, SWRESET = 1 */
#define SCIFFTX_FIFO_ON     0xE040U  /* SCIRST, SCIFFENA, TXFIFOXRESET, TXFFINTCLR */
#define SCIFFRX_FIFO_ON     0x6040U  /* RXFFOVRCLR, RXFIFORESET, RXFFINTCLR; no interrupt */
#define GPIO_MUX_PERIPH1    1U
#define GPIO_QSEL_ASYNC     3U
#define SCI_RING_LEN        32U      /* power of two; one slot stays empty. The link keeps its own queue */
#define SCI_CHAR_MASK       0x00FFU
#define SCI_RX_WORD_ERRORS  0xC000U  /* SCIRXBUF.SCIFFFE | SCIFFPE */
#define COUNT_MAX           0xFFFFU

static uint16_t s_ring[SCI_RING_LEN];   /* one character per word (char is 16 bits on the C28x) */
/* In M0 (m0data, as firmware/f28335/main.c's objects there): a slot is read only between s_tail and
 * s_head, after it was written, so nothing needs it zeroed. */
#if defined(__TMS320C28XX__)
#pragma DATA_SECTION(s_ring, "m0data")
#endif
static volatile uint16_t s_head;  /* next slot to fill: producer only */
static volatile uint16_t s_tail;  /* next slot to send: pump only (the interrupt when s_tx_irq) */
static bool s_tx_irq;             /* the transmit FIFO is fed by its interrupt */

hal_f28335_sci_errors_t hal_f28335_sci_errors;

static void count(uint16_t *c)
{
    if (*c < COUNT_MAX) {
        (*c)++;
    }
}

/* The ring into the transmit FIFO as far as it has room. */
static void fill_fifo(void)
{
    uint16_t tail = s_tail;
    uint16_t room = (uint16_t)(F28335_SCI_FIFO_DEPTH - SciaRegs.SCIFFTX.bit.TXFFST);

    while ((room > 0U) && (tail != s_head)) {
        SciaRegs.SCITXBUF = (Uint16)s_ring[tail];
        tail = (uint16_t)((tail + 1U) & (SCI_RING_LEN - 1U));
        room--;
    }
    s_tail = tail;
}

/* PIE INT9.2: the transmit FIFO is down to F28335_SCI_TX_FIFO_LEVEL words. From flash (RAM is
 * the control ISR's): its wait states cost a few cycles a word, far inside the 34 us it has. */
static HAL_INTERRUPT void sci_tx_isr(void)
{
    fill_fifo();
    if (s_tail == s_head) {
        SciaRegs.SCIFFTX.bit.TXFFIENA = 0U;   /* nothing more: quiet until the pump enables it */
    }
    SciaRegs.SCIFFTX.bit.TXFFINTCLR = 1U;
    PieCtrlRegs.PIEACK.all = PIEACK_GROUP9;
}

void f28335_sci_init(void)
{
    f28335_sci_init_at(F28335_SCI_BRR, F28335_SCI_TX_IRQ);
}

void f28335_sci_init_at(uint16_t brr, bool tx_irq)
{
    s_tx_irq = tx_irq;
    s_head = 0U;
    s_tail = 0U;
    hal_f28335_sci_errors.word_errors = 0U;
    hal_f28335_sci_errors.fifo_overflows = 0U;
    hal_f28335_sci_errors.rx_errors = 0U;

    EALLOW;
    GpioCtrlRegs.GPAPUD.bit.GPIO28 = 0U;
    GpioCtrlRegs.GPAPUD.bit.GPIO29 = 0U;
    GpioCtrlRegs.GPAQSEL2.bit.GPIO28 = GPIO_QSEL_ASYNC;
    GpioCtrlRegs.GPAMUX2.bit.GPIO28 = GPIO_MUX_PERIPH1;
    GpioCtrlRegs.GPAMUX2.bit.GPIO29 = GPIO_MUX_PERIPH1;
    EDIS;

    SciaRegs.SCICCR.all = SCICCR_8N1_ASYNC;
    SciaRegs.SCICTL1.all = SCICTL1_RESET;
    SciaRegs.SCICTL2.all = 0U;  /* no SCI interrupts */
    SciaRegs.SCIHBAUD = (Uint16)(brr >> 8);
    SciaRegs.SCILBAUD = (Uint16)(brr & 0x00FFU);
    /* the interrupt's level set, its enable left to the pump (the ring is empty) */
    SciaRegs.SCIFFTX.all = (Uint16)(SCIFFTX_FIFO_ON | (tx_irq ? F28335_SCI_TX_FIFO_LEVEL : 0U));
    SciaRegs.SCIFFRX.all = SCIFFRX_FIFO_ON;
    SciaRegs.SCIFFCT.all = 0U;  /* no delay between FIFO words */
    SciaRegs.SCICTL1.all = SCICTL1_RUN;
    if (tx_irq) {
        EALLOW;
        PieVectTable.SCITXINTA = &sci_tx_isr;
        EDIS;
        PieCtrlRegs.PIEIER9.bit.INTx2 = 1U;
        IER |= M_INT9;
    }
}

uint16_t hal_f28335_sci_tx_free(void)
{
    return (uint16_t)((s_tail - s_head - 1U) & (SCI_RING_LEN - 1U));
}

bool hal_f28335_sci_putc(uint16_t c)
{
    const uint16_t head = s_head;
    const uint16_t next = (uint16_t)((head + 1U) & (SCI_RING_LEN - 1U));
    if (next == s_tail) {
        return false;
    }
    s_ring[head] = (uint16_t)(c & SCI_CHAR_MASK);
    s_head = next;
    return true;
}

uint16_t hal_f28335_sci_write(const char *data, uint16_t len)
{
    uint16_t n = 0U;
    while (n < len && hal_f28335_sci_putc((uint16_t)data[n])) {
        n++;
    }
    return n;
}

void hal_f28335_sci_pump(void)
{
    if (!s_tx_irq) {
        fill_fifo();
    } else if (s_tail != s_head) {
        SciaRegs.SCIFFTX.bit.TXFFIENA = 1U;   /* the interrupt moves them (at once if the FIFO is low) */
    }
}

uint16_t hal_f28335_sci_read(uint16_t *buf, uint16_t max)
{
    uint16_t waiting = SciaRegs.SCIFFRX.bit.RXFFST;   /* read once: at most the FIFO's depth */
    uint16_t n = 0U;

    waiting = (waiting < max) ? waiting : max;
    for (uint16_t k = 0U; k < waiting; k++) {
        const uint16_t w = SciaRegs.SCIRXBUF.all;
        if ((w & SCI_RX_WORD_ERRORS) != 0U) {
            count(&hal_f28335_sci_errors.word_errors);   /* a garbled character: the frame's CRC would fail */
        } else {
            buf[n++] = (uint16_t)(w & SCI_CHAR_MASK);
        }
    }
    if (SciaRegs.SCIFFRX.bit.RXFFOVF != 0U) {
        count(&hal_f28335_sci_errors.fifo_overflows);
        SciaRegs.SCIFFRX.bit.RXFFOVRCLR = 1U;
    }
    if (SciaRegs.SCIRXST.bit.RXERROR != 0U) {
        /* break or overrun: the flags clear only by a software reset of the SCI (SPRUG03) */
        count(&hal_f28335_sci_errors.rx_errors);
        SciaRegs.SCICTL1.bit.SWRESET = 0U;
        SciaRegs.SCICTL1.bit.SWRESET = 1U;
    }
    return n;
}

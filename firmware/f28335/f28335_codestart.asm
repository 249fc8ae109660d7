; f28335_codestart.asm - the first code after the boot ROM's "jump to
; flash" (BEGIN, 0x33FFF6) and the entry point of a debugger load
; (--entry_point=code_start, target.mk): watchdog off, .ebss zeroed, then
; the C run-time start-up _c_int00 (which copies .cinit's initial values).
;
; Why .ebss is zeroed here: under the COFF ABI the C run-time zeroes
; nothing; only the variables .cinit initialises get a value, every other
; static starts with what the RAM held (random after power-up, the last
; run's after a watchdog reset). The application initialises everything
; it reads (tests/test_app_init_pattern.c runs app_init on pattern-filled
; memory); zeroing puts the rest (the HAL's and C2000Ware's statics) in a
; known state too, before _c_int00 writes .cinit's values on top.
; The range comes from the linker (f28335_flash.cmd: RUN_START(_EbssRunStart),
; RUN_SIZE(_EbssRunSize) of .ebss), so it follows the section.
;
; Watchdog: off first (WDCR = 0x0068: WDDIS = 1, WDCHK = 101b; SPRUFB0
; "Watchdog Block"), as C2000Ware's DSP2833x_CodeStartBranch.asm does:
; zeroing up to 8K words and .cinit outlast its 4.37 ms reset timeout.
; WDFLAG (bit 7, write 1 to clear) is written 0: the reset cause survives
; for hal_init, which reads it before its own write.
; hal_init keeps it off and hal_isr_attach turns it on for good.

WDCR            .set    0x7029          ; watchdog control register (EALLOW protected)
WDCR_DISABLE    .set    0x0068          ; WDDIS | WDCHK = 101b

        .ref    _c_int00
        .ref    _EbssRunStart
        .ref    _EbssRunSize
        .global code_start

        .sect   "codestart"             ; 2 words at BEGIN: the branch only
code_start:
        LB      startup_clear

        .text
startup_clear:
        SETC    OBJMODE                 ; C28x object mode (a debugger load may start after a CPU reset)
        EALLOW
        MOVZ    DP, #WDCR >> 6
        MOV     @WDCR, #WDCR_DISABLE
        EDIS
        MOVL    XAR4, #_EbssRunStart    ; first word of .ebss
        MOVL    XAR5, #_EbssRunSize     ; words to clear (< 64K: AR5 counts)
        B       clear_test, UNC
clear_word:
        MOV     *XAR4++, #0
clear_test:
        BANZ    clear_word, AR5--       ; AR5 != 0: one more word (AR5 decremented either way)
        LB      _c_int00

        .end

; ld1: one raw word, into every written lane.
        .data
        .word   0xdeadbeef
w1:     .word   0x7f800001
        .text
raygen:
        li      r1.x, DEVICE_LAUNCH_BASE
        ld1     r2, [r1 + LAUNCH_HEIGHT_AT]
        li      r3, 0x33
        ld1     r3.yz, [r1 + LAUNCH_FRAMEBUFFER_AT]
        li      r4.w, w1
        ld1     r5, [r4.w - 4]
        ld1     r6, [r4.w]                      ; a signalling NaN, raw
        halt

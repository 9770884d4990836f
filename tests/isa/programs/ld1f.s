; ld1f in fp16: one fp32 word rounded into the format, into every written lane.
        .data
vals:   .float  0.1, 70000.0, -2.5
        .word   0x00000001
        .text
raygen:
        li      r1.x, vals
        ld1f    r2, [r1]
        ld1f    r3, [r1 + 4]
        li      r4, 0x44
        ld1f    r4.xw, [r1 + 8]
        ld1f    r5, [r1 + 12]
        halt

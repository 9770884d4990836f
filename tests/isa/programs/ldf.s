; ldf in rpu24: each fp32 word is rounded into the format (17 significant bits, input
; flush, canonical NaN); ld of the same words moves the raw bits.
        .data
vals:   .float  0.1, 1.0000076293945312, 1.0000228881835938, 1e20
more:   .word   0x00000001, 0x7fc00001, 0x1fec1e4a, 0xbf800000
        .text
raygen:
        li      r1.x, vals
        ldf     r2, [r1]
        ld      r3, [r1]                        ; raw, for comparison
        ldf     r4, [r1 + 16]
        li      r5, 0x55
        ldf     r5.yw, [r1 + 16]
        halt

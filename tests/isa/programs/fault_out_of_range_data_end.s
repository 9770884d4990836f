; out-of-range access: one word past the firmware's 8 bytes of .data.
        .data
two:    .word   1, 2
        .text
raygen:
        li      r1.x, two
        ld1     r2, [r1 + 4]                    ; the last word: fine
        ld1     r2, [r1 + 8]
        halt

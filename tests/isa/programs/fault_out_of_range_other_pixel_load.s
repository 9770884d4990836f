; out-of-range access: a 16-byte load that starts in the own pixel (1 of 3 x 1) and runs
; into pixel 2.
raygen:
        li      r1.x, DEVICE_FRAMEBUFFER_BASE
        ld      r3, [r1 + 20]
        halt

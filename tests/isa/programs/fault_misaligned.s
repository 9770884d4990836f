; misaligned access: every address must be a multiple of 4.
raygen:
        li      r1.x, DEVICE_LAUNCH_BASE
        ld      r2, [r1 + 4]                    ; aligned: fine
        ld1     r2, [r1 + 2]
        halt

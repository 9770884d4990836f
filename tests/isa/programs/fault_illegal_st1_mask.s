; illegal instruction: st1 stores lane x; any other write mask is illegal.
raygen:
        li      r1.x, DEVICE_FRAMEBUFFER_BASE
        st1     [r1], r2.x                      ; fine
        st1     [r1], r2.y
        halt

; illegal instruction: st's data register (the dst field) past the register count.
raygen:
        li      r1.x, DEVICE_FRAMEBUFFER_BASE
        st      [r1], r33
        halt

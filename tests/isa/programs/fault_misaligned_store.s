; misaligned access: a store into the thread's own pixel, 2 bytes off.
raygen:
        li      r1.x, DEVICE_FRAMEBUFFER_BASE
        st1     [r1 + 6], r2.x
        halt

; st1: lane x of the data register (write mask .x) to one word, raw.
raygen:
        li      r1.x, DEVICE_LAUNCH_BASE
        ld1     r1.y, [r1 + LAUNCH_FRAMEBUFFER_AT]
        rdsr    r2, pixel
        imuli   r2.z, r2.z, 16
        iadd    r3.x, r1.y, r2.z
        li      r4.x, 0x11111111
        li      r4.y, 0x22222222
        li      r4.z, 0x7f800001                ; a signalling NaN, stored raw
        li      r4.w, 0x80000000
        st1     [r3 + 12], r4.x
        mov     r5.x, r4.y
        st1     [r3], r5.x
        mov     r5.x, r4.z
        st1     [r3 + 4], r5.x
        mov     r5.x, r4.w
        st1     [r3 + 8], r5.x
        halt

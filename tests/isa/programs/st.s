; st: the lanes of the data register's write mask go to address + 4i, here the
; thread's own framebuffer pixel: framebuffer address + 16 * pixel index. Loads read
; the pixel back.
raygen:
        li      r1.x, DEVICE_LAUNCH_BASE
        ld1     r1.y, [r1 + LAUNCH_FRAMEBUFFER_AT]
        rdsr    r2, pixel                       ; (x, y, y * width + x, 0)
        shli    r2.z, r2.z, 4
        iadd    r3.x, r1.y, r2.z                ; the pixel's 16 bytes
        lif     r4.x, 1.0
        lif     r4.y, 2.0
        lif     r4.z, 3.0
        lif     r4.w, 4.0
        st      [r3], r4                        ; (1, 2, 3, 4)
        ld      r6, [r3]
        li      r5.y, 0x0000bbbb
        li      r5.w, 0x7fc00001
        st      [r3], r5.yw                     ; lanes y, w only: (1, 0xbbbb, 3, NaN payload)
        st      [r3 + 8], r4.x                  ; lane x at +8: z = 1.0
        ld      r7, [r3]
        halt

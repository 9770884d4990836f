; out-of-range access: the framebuffer of another thread's pixel. The thread runs pixel
; 1 of a 2 x 1 launch (0x80000010..0x8000001f); pixel 0 is at 0x80000000.
raygen:
        li      r1.x, DEVICE_FRAMEBUFFER_BASE
        st1     [r1 + 16], r2.x                 ; its own pixel: fine
        ld      r3, [r1 + 16]                   ; and reading it back
        st1     [r1 + 12], r2.x                 ; the last word of pixel 0
        halt

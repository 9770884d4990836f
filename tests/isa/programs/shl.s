; shl: a << (b & 31): shift counts of 32 and more are masked, not "all bits out".
raygen:
        li      r1, 1
        li      r2.x, 31
        li      r2.y, 32                        ; & 31 = 0
        li      r2.z, 33                        ; & 31 = 1
        li      r2.w, -1                        ; & 31 = 31
        shl     r3, r1, r2
        li      r4.x, 0xffffffff
        li      r4.y, 0x12345678
        li      r5.x, 4
        li      r5.y, 0x100                     ; & 31 = 0
        li      r6, 0x88
        shl     r6.xy, r4, r5                   ; (0xffffffff << 4, 0x12345678 << 0)
        halt

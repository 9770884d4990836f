; shr: logical a >> (b & 31): zeros shift in, also for negative values.
raygen:
        li      r1, 0x80000000
        li      r2.x, 31
        li      r2.y, 32                        ; & 31 = 0
        li      r2.z, 36                        ; & 31 = 4
        li      r2.w, 1
        shr     r3, r1, r2
        li      r4, 0x88
        li      r5.x, 0xfffffff0
        li      r5.y, 4
        shr     r4.zw, r5.x, r5.y               ; 0x0fffffff
        halt

; sra: arithmetic a >> (b & 31): the sign bit shifts in.
raygen:
        li      r1.x, 0x80000000
        li      r1.y, -16
        li      r1.z, -1
        li      r1.w, 0x40000000
        li      r2.x, 31
        li      r2.y, 2
        li      r2.z, 5
        li      r2.w, 30
        sra     r3, r1, r2
        li      r4.x, -16
        li      r4.y, 0x80000000
        li      r5.x, 32                        ; & 31 = 0: unchanged
        li      r5.y, 63                        ; & 31 = 31
        li      r6, 0x88
        sra     r6.yz, r4.wxy, r5.wxy           ; (-, -16 >> 32, 0x80000000 >> 63, -)
        halt

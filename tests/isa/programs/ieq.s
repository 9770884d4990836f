; ieq: raw bit equality: +0 and -0 differ, a NaN equals itself (unlike feq).
raygen:
        li      r1.x, 0
        li      r1.y, 0x7fc00000
        li      r1.z, 42
        li      r1.w, -1
        li      r2.x, 0x80000000
        li      r2.y, 0x7fc00000
        li      r2.z, 43
        li      r2.w, 0xffffffff
        ieq     r3, r1, r2
        li      r4, 0x4e4e4e4e
        ieq     r4.x, r1.z, r1.z
        ieq     r4.y, r1.z, r2.z
        halt

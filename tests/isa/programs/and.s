; and, per lane on raw bits; swizzle, write mask.
raygen:
        li      r1.x, 0xff00ff00
        li      r1.y, 0x12345678
        li      r1.z, 0xffffffff
        li      r1.w, 0x80000000
        li      r2.x, 0x0ff00ff0
        li      r2.y, 0xf0f0f0f0
        li      r2.z, 0
        li      r2.w, 0x7fffffff
        and     r3, r1, r2
        li      r4, 0x3333
        and     r4.z, r1.y, r1.z                ; 0x12345678 & ~0
        halt

; iadd: a + b mod 2^32 per lane, raw bits; swizzle, write mask.
raygen:
        li      r1.x, 0xffffffff
        li      r1.y, 0x7fffffff
        li      r1.z, 0x3f800000                ; 1.0 as a float: added as an integer
        li      r1.w, -5
        li      r2.x, 1
        li      r2.y, 1
        li      r2.z, 0x3f800000
        li      r2.w, 3
        iadd    r3, r1, r2
        li      r4, 0x10
        iadd    r4.xw, r1.wzyx, r2.x            ; (-5 + 1, -, -, -1 + 1)
        halt

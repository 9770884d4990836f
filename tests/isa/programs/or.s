; or, per lane on raw bits; swizzle, write mask.
raygen:
        li      r1.x, 0xff00ff00
        li      r1.y, 0x12345678
        li      r1.z, 0
        li      r1.w, 0x80000000
        li      r2.x, 0x0ff00ff0
        li      r2.y, 0x0f0f0f0f
        li      r2.z, 0
        li      r2.w, 0x7fffffff
        or      r3, r1, r2
        li      r4, 0x3333
        or      r4.xy, r1.w, r2.yx              ; (0x80000000 | 0x0f0f0f0f, | 0x0ff00ff0)
        halt

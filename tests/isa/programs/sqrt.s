; sqrt: correctly rounded; sqrt(-0) = -0, sqrt(+inf) = +inf, negative -> NaN, DAZ.
raygen:
        lif     r1.x, 2.0
        lif     r1.y, 3.0
        lif     r1.z, 0.25
        li      r1.w, 0x3f800002                ; 1 + 2^-22
        sqrt    r2, r1
        lif     r3.x, -0.0
        lif     r3.y, inf
        lif     r3.z, -1.0
        lif     r3.w, -inf
        sqrt    r4, r3
        li      r5.x, 0x80000001                ; -subnormal: -0, so -0
        li      r5.y, 0x00000001                ; +subnormal: +0
        li      r5.z, 0x7f7fffff                ; largest finite
        li      r5.w, 0x00800000                ; 2^-126 -> 2^-63
        sqrt    r6, r5
        li      r7, 0x3c3c3c3c
        lif     r8.x, -9.0
        sqrt    r7.z, |r8|.x                    ; 3; x, y, w keep
        halt

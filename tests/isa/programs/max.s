; max: -0 < +0 (either order), any NaN gives the canonical NaN, subnormals are zeros,
; infinities order; modifiers, write mask.
raygen:
        lif     r1.x, -0.0
        lif     r1.y, 1.0
        lif     r1.z, inf
        li      r1.w, 0xff800001                ; a negative signalling NaN
        max     r2.x, r1.x, r0.x                ; max(-0, +0) = +0
        max     r2.y, r0.x, r1.x                ; max(+0, -0) = +0
        max     r2.z, r1.z, r1.y                ; inf
        max     r2.w, r1.w, r1.y                ; max(NaN, 1) = NaN (0x7fc00000)
        ; subnormals read as zeros: max(-sub, -1) = -0; max(-sub, +0) = +0
        li      r3.x, 0x807fffff
        max     r4.x, r3.x, -r1.y
        max     r4.y, r3.x, r0.x
        max     r4.z, -r1.z, r1.w               ; max(-inf, NaN) = NaN
        max     r4.w, -r1.z, -|r1|.y            ; -1
        lif     r6.x, 1.0
        lif     r6.y, 5.0
        lif     r6.z, -3.0
        lif     r6.w, 4.0
        li      r7, 0x0000abcd
        max     r7.xzw, r6, -r6.wzyx            ; (max(1,-4), -, max(-3,-5), max(4,-1))
        halt

; flt: a < b, false if either is NaN; -0 < +0 is false (they are equal).
raygen:
        lif     r1.x, -1.0
        lif     r1.y, -0.0
        lif     r1.z, nan
        lif     r1.w, -inf
        lif     r2.x, 0.0
        lif     r2.y, 0.0
        lif     r2.z, 1.0
        lif     r2.w, inf
        flt     r3, r1, r2                      ; (-1 < 0, -0 < +0, NaN < 1, -inf < inf)
        flt     r4, r2, r1                      ; the reverse
        lif     r5.x, 1.0
        li      r5.y, 0x00000007                ; subnormal: +0
        flt     r6.x, r5.x, r5.x                ; 1 < 1
        flt     r6.y, r5.y, r5.x                ; +0 < 1
        flt     r6.z, r1.y, r5.y                ; -0 < (sub = +0)
        flt     r6.w, r5.x, r1.z                ; 1 < NaN
        li      r7, 0x5a5a5a5a
        flt     r7.zw, -|r5|.x, r1.y            ; -1 < -0 in z, w
        halt

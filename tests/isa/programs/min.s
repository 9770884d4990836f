; min: -0 < +0 (either order), any NaN gives the canonical NaN (not minNum), subnormal
; inputs are zeros of their sign, infinities order; modifiers, write mask.
raygen:
        lif     r1.x, -0.0
        lif     r1.y, 1.0
        lif     r1.z, -inf
        li      r1.w, 0x7fc00123                ; NaN with a payload
        min     r2.x, r1.x, r0.x                ; min(-0, +0) = -0
        min     r2.y, r0.x, r1.x                ; min(+0, -0) = -0
        min     r2.z, r1.z, r1.y                ; -inf
        min     r2.w, r1.y, r1.w                ; min(1, NaN) = NaN
        ; subnormals read as zeros: min(+sub, 1) is +0 (not the subnormal's bits);
        ; min(+sub, -sub) = min(+0, -0) = -0
        li      r3.x, 0x00000005
        li      r3.y, 0x80000005
        min     r4.x, r3.x, r1.y
        min     r4.y, r3.x, r3.y
        min     r4.z, r1.w, r1.z                ; min(NaN, -inf) = NaN
        lif     r5, 2.0
        min     r4.w, -r5.x, r1.y               ; -2
        ; per lane, with a swizzle and a write mask
        lif     r6.x, 1.0
        lif     r6.y, 5.0
        lif     r6.z, -3.0
        lif     r6.w, 4.0
        li      r7, 0x0000abcd
        min     r7.xyw, r6, |r6|.wzyx           ; (min(1,4), min(5,3), -, min(4,1))
        halt

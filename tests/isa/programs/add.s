; add: round to nearest even, signed zeros, input flush (DAZ), result flush (FTZ),
; overflow, invalid (inf - inf), NaN canonicalisation; swizzle, neg/abs, write mask.
raygen:
        lif     r1, 1.0
        lif     r2.x, 5.9604644775390625e-08    ; 2^-24: 1 + 2^-24 is a tie
        lif     r2.y, 1.78813934326171875e-07   ; 3 * 2^-24: 1 + 1.5 ulp is a tie
        lif     r2.z, 2.384185791015625e-07     ; 2^-22
        lif     r2.w, 1.1920928955078125e-07    ; 2^-23
        add     r3, r1, r2
        ; 1.1f + 2.2f in fp32 (not in double)
        lif     r4.x, 1.1
        lif     r4.y, 2.2
        add     r5.x, r4.x, r4.y
        ; signed zeros: x + (-x) = +0, (-0) + (-0) = -0, (+0) + (-0) = +0
        lif     r4.z, -0.0
        add     r5.y, r4.x, -r4.x
        add     r5.z, r4.z, r4.z
        add     r5.w, r0.x, r4.z
        ; DAZ: subnormal inputs are zeros of their sign
        li      r6.x, 0x80000001                ; -subnormal
        li      r6.y, 0x007fffff                ; largest subnormal
        add     r7.x, r6.x, r4.z                ; (-0) + (-0) = -0
        add     r7.y, r6.y, r6.y                ; 0 + 0, not 2^-125 - 2^-148 (a normal)
        ; FTZ: (2^-126 + 2^-149) - 2^-126 = 2^-149 exactly, below the smallest normal
        li      r6.z, 0x00800001
        li      r6.w, 0x00800000
        add     r7.z, r6.z, -r6.w               ; +0
        add     r7.w, r6.w, -r6.z               ; -0 (the exact result's sign)
        ; overflow, inf - inf, NaN with payload in
        li      r8.x, 0x7f7fffff                ; largest finite
        lif     r8.y, inf
        li      r8.z, 0x7f800001                ; a signalling NaN
        add     r9.x, r8.x, r8.x                ; inf
        add     r9.y, r8.y, -r8.y               ; NaN
        add     r9.z, r8.z, r1.x                ; canonical NaN
        add     r9.w, -r8.x, -|r8|.x            ; -inf
        ; swizzle, |.| and write mask: r10.yw = |r11|.wzyx + r11.x
        lif     r11.x, 1.0
        lif     r11.y, -2.0
        lif     r11.z, 3.0
        lif     r11.w, -4.0
        li      r10, 0x12345678
        add     r10.yw, |r11|.wzyx, r11.x
        halt

; mul: exact products, rounding, signed zeros, 0 * inf, overflow, FTZ (and the
; tininess-after-rounding case of docs/numbers.md), DAZ inputs; modifiers, write mask.
raygen:
        lif     r1.x, 3.0
        lif     r1.y, 0.5
        lif     r1.z, -0.0
        lif     r1.w, inf
        mul     r2.x, r1.x, r1.y                ; 1.5
        mul     r2.y, r1.z, r1.x                ; -0 * 3 = -0
        mul     r2.z, r1.z, -r1.x               ; -0 * -3 = +0
        mul     r2.w, r0.x, r1.w                ; 0 * inf = NaN
        ; (1 + 2^-12)^2 = 1 + 2^-11 + 2^-24: the 2^-24 is half an ulp, a tie, even
        ; (1 + 2^-11) wins
        lif     r3.x, 1.000244140625
        ; 2^-63 * 2^-64 = 2^-127 is below the smallest normal: a zero of the product's sign
        lif     r3.y, 1.0842021724855044e-19    ; 2^-63
        lif     r3.z, 5.421010862427522e-20     ; 2^-64
        mul     r4.x, r3.x, r3.x
        mul     r4.y, r3.y, r3.z
        mul     r4.z, -r3.y, r3.z
        ; 0x3f000001 * 0x00fffffe = 2^-126 (1 - 2^-46) rounds up to 2^-126: not flushed
        li      r5.x, 0x3f000001
        li      r5.y, 0x00fffffe
        mul     r4.w, r5.x, r5.y
        ; DAZ: the subnormal 2^-127 (0x00400000) is read as 0, so 2^127 * it is 0, not 1
        li      r5.z, 0x00400000
        li      r5.w, 0x7f000000                ; 2^127
        mul     r6.x, r5.z, r5.w
        ; overflow: 2^127 * 2 = inf, with either sign
        lif     r7, 2.0
        mul     r6.y, r5.w, r7.x
        mul     r6.z, -|r5|.w, r7.x
        ; NaN payloads are not propagated
        li      r7.w, 0xffc01234
        mul     r6.w, r7.w, r7.x
        ; swizzle + write mask
        lif     r8.x, 1.0
        lif     r8.y, 2.0
        lif     r8.z, 3.0
        lif     r8.w, 4.0
        li      r9, 7
        mul     r9.xz, r8.zw, -r8               ; (z*x, w*y, w*z, w*w)
        halt

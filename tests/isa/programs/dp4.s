; dp4: every written lane = (a.x*b.x + a.y*b.y) + (a.z*b.z + a.w*b.w), each product
; and sum rounded on its own (a pairwise tree, not a left-to-right chain).
raygen:
        lif     r1, 1.0
        lif     r2.x, 1.0
        lif     r2.yzw, 5.9604644775390625e-08  ; 2^-24
        ; pairs: (1 + 2^-24) -> 1 (tie, even); (2^-24 + 2^-24) = 2^-23; 1 + 2^-23 exact.
        ; A left-to-right chain gives 1.0; the exact sum 1 + 3*2^-24 gives 1 + 2^-22.
        dp4     r3, r1, r2
        ; write mask and swizzle: r4.xw = (4,3,2,1) . (1,2,3,4) = 4 + 6 + 6 + 4 = 20
        lif     r5.x, 1.0
        lif     r5.y, 2.0
        lif     r5.z, 3.0
        lif     r5.w, 4.0
        li      r4, 9
        dp4     r4.xw, r5.wzyx, r5
        ; neg and abs: -|r6| . r5 with r6 = (-1, 1, -1, 1): -(1 + 2 + 3 + 4)
        lif     r6.xz, -1.0
        lif     r6.yw, 1.0
        dp4     r7, -|r6|, r5
        ; lane w counts: inf * 0 there makes the sum NaN
        lif     r8.w, inf
        dp4     r9, r8, r0
        ; -2^127*2 + 2^127*2: the products overflow to -inf and +inf first: NaN
        li      r10.x, 0xff000000               ; -2^127
        li      r10.y, 0x7f000000               ; 2^127
        lif     r11.xy, 2.0
        dp4     r12, r10, r11
        halt

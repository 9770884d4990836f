; dp3: every written lane = (a.x*b.x + a.y*b.y) + a.z*b.z, each product and sum
; rounded on its own; lane w of the sources is not read.
raygen:
        ; products rounded: (1 + 2^-12)^2 rounds to 1 + 2^-11 (the 2^-24 is a tie to
        ; even), which -(1 + 2^-11) cancels exactly: +0, not 2^-24
        lif     r1.x, 1.000244140625            ; 1 + 2^-12
        lif     r1.y, 1.00048828125             ; 1 + 2^-11
        lif     r1.z, 0.0
        lif     r1.w, nan                       ; not read by dp3
        lif     r2.x, 1.000244140625
        lif     r2.y, -1.0
        lif     r2.z, 0.0
        lif     r2.w, inf
        dp3     r3, r1, r2
        ; the order: (1*1 + 1*2^-24) rounds to 1 (tie, even), then + 2^-24 rounds to 1
        ; again. 1 + (2^-24 + 2^-24) or the exact sum would give 1 + 2^-23.
        lif     r4, 1.0
        lif     r5.x, 1.0
        lif     r5.yz, 5.9604644775390625e-08   ; 2^-24
        li      r6, 0x55555555
        dp3     r6.yzw, r4, r5
        ; x and y first: (2^-24 + 2^-24) + 1 = 1 + 2^-23 exactly
        lif     r7.xy, 5.9604644775390625e-08
        lif     r7.z, 1.0
        dp3     r8, r4, r7
        ; modifiers and swizzles: -(r9.zyx) . |r10| = -(3*1 + 2*2 + 1*3) = -10
        lif     r9.x, 1.0
        lif     r9.y, 2.0
        lif     r9.z, 3.0
        lif     r10.x, -1.0
        lif     r10.y, 2.0
        lif     r10.z, -3.0
        dp3     r11, -r9.zyx, |r10|
        ; inf * 0 in one product: NaN
        lif     r12.x, inf
        dp3     r13, r12, r0
        halt

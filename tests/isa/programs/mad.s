; mad: one rounding. 1 + 2^-23 squared is 1 + 2^-22 + 2^-46; minus (1 + 2^-22) leaves
; 2^-46 only if the product is not rounded first.
raygen:
        lif     r1, 1.00000011920928955078125   ; 1 + 2^-23
        lif     r2, -1.0000002384185791015625   ; -(1 + 2^-22)
        mad     r3, r1, r1, r2
        lif     r4, 2.0
        lif     r5, 3.0
        lif     r6, 0.5
        mad     r7.xy, |r4|, -r5, r6            ; |2| * -3 + 0.5
        ; fma(0, inf, c) is invalid whatever c is
        lif     r8.x, inf
        mad     r9.x, r0.x, r8.x, r1.x
        ; signed zeros: 1 * -0 + -0 = -0; 1 * +0 + -0 = +0
        lif     r8.y, -0.0
        lif     r8.z, 1.0
        mad     r9.y, r8.z, r8.y, r8.y
        mad     r9.z, r8.z, r0.x, r8.y
        ; no intermediate overflow: max * 2 - max = max
        li      r8.w, 0x7f7fffff
        lif     r10.x, 2.0
        mad     r9.w, r8.w, r10.x, -r8.w
        ; no intermediate flush: 2^-63 * 2^-64 = 2^-127 (subnormal) + 2^-126 = 1.5 * 2^-126;
        ; alone, 2^-127 flushes to +0
        lif     r10.y, 1.0842021724855044e-19   ; 2^-63
        lif     r10.z, 5.421010862427522e-20    ; 2^-64
        li      r10.w, 0x00800000               ; 2^-126
        mad     r11.x, r10.y, r10.z, r10.w
        mad     r11.y, r10.y, r10.z, r0.x
        mad     r11.z, -r10.y, r10.z, r0.x      ; -0
        halt

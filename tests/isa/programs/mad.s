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
        halt

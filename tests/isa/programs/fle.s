; fle: a <= b, false if either is NaN; -0 <= +0 and +0 <= -0 are true.
raygen:
        lif     r1.x, -1.0
        lif     r1.y, -0.0
        lif     r1.z, nan
        lif     r1.w, inf
        lif     r2.x, 0.0
        lif     r2.y, 0.0
        lif     r2.z, nan
        lif     r2.w, inf
        fle     r3, r1, r2                      ; (-1 <= 0, -0 <= +0, NaN <= NaN, inf <= inf)
        fle     r4, r2, r1                      ; (0 <= -1, +0 <= -0, NaN <= NaN, inf <= inf)
        lif     r5.x, 2.0
        lif     r5.y, 1.0
        fle     r6.x, r5.x, r5.y                ; 2 <= 1
        fle     r6.y, r5.y, r5.x                ; 1 <= 2
        fle     r6.z, r5.y, r1.z                ; 1 <= NaN
        fle     r6.w, -r5.x, -r5.y              ; -2 <= -1
        li      r7, 0x5a5a5a5a
        fle     r7.x, |r1|.x, r5.y              ; 1 <= 1
        halt

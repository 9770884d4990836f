; fne: true if either input is NaN; +0 and -0 (and subnormals) are equal.
raygen:
        lif     r1.x, 1.0
        lif     r1.y, -0.0
        lif     r1.z, nan
        li      r1.w, 0x80000003                ; -subnormal: reads as -0
        lif     r2.x, 1.0
        lif     r2.y, 0.0
        lif     r2.z, nan
        lif     r2.w, 0.0
        fne     r3, r1, r2                      ; (1 != 1, -0 != +0, NaN != NaN, sub != 0)
        lif     r4.x, 2.0
        fne     r5.x, r1.x, r4.x                ; 1 != 2
        fne     r5.y, r1.z, r1.x                ; NaN != 1
        fne     r5.z, r1.x, -r2.x               ; 1 != -1
        fne     r5.w, r1.x, |r2|.x              ; 1 != 1
        li      r6, 0x5a5a5a5a
        fne     r6.xw, r4.x, r1.x               ; 2 != 1 in x, w
        halt

; rcp: 1/a correctly rounded; 1/±0 = ±inf, 1/±inf = ±0, NaN, DAZ input, FTZ result.
raygen:
        lif     r1.x, 3.0
        lif     r1.y, -2.0
        lif     r1.z, 10.0
        lif     r1.w, 4.0
        rcp     r2, r1                          ; 1/3, -0.5, 1/10, 0.25
        lif     r3.x, -0.0
        lif     r3.z, inf
        lif     r3.w, -inf
        rcp     r4, r3                          ; (-inf, +inf (1/+0), +0, -0)
        li      r5.x, 0x00000001                ; subnormal: read as +0, 1/+0 = inf
        li      r5.y, 0x7f000000                ; 2^127: 2^-127 flushes to +0
        li      r5.z, 0x00800000                ; 2^-126: 2^126 = 0x7e800000
        li      r5.w, 0x7fa00000                ; NaN with payload
        rcp     r6, r5
        ; modifiers and mask: -|r1|.y = -2 -> -0.5 in y only
        li      r7, 0x01010101
        rcp     r7.y, -|r1|.y
        rcp     r7.z, -r5.y                     ; -2^-127 flushes to -0
        halt

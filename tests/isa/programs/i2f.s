; i2f: the signed 32-bit integer, rounded (ties to even) into fp32; write mask.
raygen:
        li      r1.x, 16777217                  ; 2^24 + 1
        li      r1.y, 16777219                  ; 2^24 + 3
        li      r1.z, -16777219
        li      r1.w, 0x7fffffc0                ; 2^31 - 64
        i2f     r2, r1
        li      r3.x, 0x80000000                ; INT32_MIN
        li      r3.y, 0x7fffffff                ; INT32_MAX
        li      r3.z, -1
        li      r3.w, 0
        i2f     r4, r3
        li      r5.x, 0x7fffffbf                ; 2^31 - 65
        li      r5.y, 123456789
        li      r6, 0x42424242
        i2f     r6.yw, r5.xyzx                  ; y <- 123456789, w <- 2^31 - 65
        halt

; srai: arithmetic a >> (imm & 31).
raygen:
        li      r1.x, 0x80000000
        li      r1.y, -7
        li      r1.z, 0x7fffffff
        li      r1.w, -1
        srai    r2, r1, 31
        srai    r3, r1, 1                       ; -7 >> 1 = -4 (toward -inf)
        srai    r4, r1, 33                      ; & 31 = 1
        srai    r5, r1, 64                      ; & 31 = 0
        halt

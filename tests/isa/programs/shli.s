; shli: a << (imm & 31).
raygen:
        li      r1.x, 1
        li      r1.y, 0xffffffff
        li      r1.z, 0x12345678
        li      r1.w, 3
        shli    r2, r1, 31
        shli    r3, r1, 32                      ; & 31 = 0: unchanged
        shli    r4, r1, 36                      ; & 31 = 4
        halt

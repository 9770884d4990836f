; shri: logical a >> (imm & 31).
raygen:
        li      r1.x, 0x80000000
        li      r1.y, 0xffffffff
        li      r1.z, 0x12345678
        li      r1.w, 1
        shri    r2, r1, 31
        shri    r3, r1, 32                      ; & 31 = 0
        li      r4, 0x44
        shri    r4.xz, r1, 0x24                 ; & 31 = 4
        halt

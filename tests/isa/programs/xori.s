; xori: a ^ imm per lane; write mask.
raygen:
        li      r1.x, 0x12345678
        li      r1.y, 0xffffffff
        li      r1.z, 0x3f800000
        li      r1.w, 0x0000ffff
        xori    r2, r1, 0x80000000              ; flips the sign bit
        li      r3, 0x44
        xori    r3.w, r1.w, -1                  ; ~0x0000ffff
        halt

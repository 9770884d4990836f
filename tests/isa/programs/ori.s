; ori: a | imm per lane; write mask.
raygen:
        li      r1.x, 0x12345678
        li      r1.y, 0
        li      r1.z, 0x80000000
        li      r1.w, 0x0000000f
        ori     r2, r1, 0x0f0000f0
        li      r3, 0x44
        ori     r3.yz, r1.y, 0x80000000
        halt

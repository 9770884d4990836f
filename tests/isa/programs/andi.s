; andi: a & imm per lane; write mask.
raygen:
        li      r1.x, 0x12345678
        li      r1.y, 0xffffffff
        li      r1.z, 0x80000001
        li      r1.w, 0xabcdef01
        andi    r2, r1, 0x0000ff0f
        li      r3, 0x44
        andi    r3.x, r1.w, -256                ; 0xffffff00
        halt

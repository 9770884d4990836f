; iaddi: a + imm mod 2^32; negative immediates; swizzle, write mask.
raygen:
        li      r1.x, 0xffffffff
        li      r1.y, 10
        li      r1.z, 0x7fffffff
        li      r1.w, 0
        iaddi   r2, r1, 1                       ; (0, 11, 0x80000000, 1)
        iaddi   r3, r1, -11                     ; (-12, -1, 0x7ffffff4, -11)
        li      r4, 0x44
        iaddi   r4.yw, r1.yx, 0x80000000
        halt

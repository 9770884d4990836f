; iltu: unsigned a < b.
raygen:
        li      r1.x, -1
        li      r1.y, 0x7fffffff
        li      r1.z, 5
        li      r1.w, 0
        li      r2.x, 0
        li      r2.y, 0x80000000
        li      r2.z, 5
        li      r2.w, 1
        iltu    r3, r1, r2                      ; (0xffffffff < 0, 0x7fffffff < 0x80000000, 5 < 5, 0 < 1)
        li      r4, 0x4c4c4c4c
        iltu    r4.x, r2.x, r1.x                ; 0 < 0xffffffff
        halt

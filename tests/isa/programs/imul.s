; imul: the low 32 bits of the product (same for signed and unsigned).
raygen:
        li      r1.x, 0x10000
        li      r1.y, -3
        li      r1.z, 0xffffffff
        li      r1.w, 0x12345
        li      r2.x, 0x10000
        li      r2.y, 5
        li      r2.z, 0xffffffff
        li      r2.w, 0x6789
        imul    r3, r1, r2
        li      r4, 0x66
        imul    r4.w, r1.y, r1.y                ; 9
        halt

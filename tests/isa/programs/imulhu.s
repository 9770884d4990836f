; imulhu: the high 32 bits of the unsigned 64-bit product.
raygen:
        li      r1.x, 0xffffffff
        li      r1.y, 0x10000
        li      r1.z, 0xffffffff                ; -1 as signed: still 2^32 - 1 here
        li      r1.w, 0x80000000
        li      r2.x, 0xffffffff
        li      r2.y, 0x10000
        li      r2.z, 2
        li      r2.w, 0x80000000
        imulhu  r3, r1, r2
        li      r4, 0x77
        li      r5.x, 0x12345678
        li      r5.y, 0x9abcdef0
        imulhu  r4.xy, r5.x, r5.y               ; x, y: 0x12345678 * 0x9abcdef0 >> 32
        imulhu  r4.z, r5.x, r0.x                ; 0
        halt

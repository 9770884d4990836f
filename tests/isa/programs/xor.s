; xor, per lane on raw bits; write mask.
raygen:
        li      r1.x, 0xff00ff00
        li      r1.y, 0x12345678
        li      r1.z, 0x80000000
        li      r1.w, 0xdeadbeef
        li      r2.x, 0x0ff00ff0
        li      r2.y, 0xffffffff
        li      r2.z, 0x3f800000
        li      r2.w, 0xdeadbeef
        xor     r3, r1, r2
        li      r4, 0x3333
        xor     r4.w, r1.z, r1.z                ; 0
        halt

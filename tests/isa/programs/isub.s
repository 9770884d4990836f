; isub: a - b mod 2^32.
raygen:
        li      r1.x, 0
        li      r1.y, 0x80000000
        li      r1.z, 100
        li      r1.w, 5
        li      r2.x, 1
        li      r2.y, 1
        li      r2.z, 58
        li      r2.w, 0xfffffffb                ; -5
        isub    r3, r1, r2
        li      r4, 0x44
        isub    r4.yz, r2, r1.x                 ; (-, 1 - 0, 58 - 0, -)
        isub    r5, r1, r1                      ; 0
        halt

; imuli: a * imm mod 2^32.
raygen:
        li      r1.x, -7
        li      r1.y, 0x10000
        li      r1.z, 0x9e3779b9
        li      r1.w, 0
        imuli   r2, r1, 3
        imuli   r3, r1, 0x10000
        li      r4, 0x44
        imuli   r4.z, r1.x, -1                  ; 7
        halt

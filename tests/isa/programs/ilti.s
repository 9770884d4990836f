; ilti: signed a < imm.
raygen:
        li      r1.x, -5
        li      r1.y, 5
        li      r1.z, 0x80000000
        li      r1.w, -4
        ilti    r2, r1, -4                      ; (-5 < -4, 5 < -4, MIN < -4, -4 < -4)
        ilti    r3, r1, 0x80000000              ; nothing is below INT32_MIN
        li      r4, 0x44
        ilti    r4.y, r1.y, 6
        halt

; bnz: taken if lane x of the swizzled register is not 0 (raw bits).
raygen:
        li      r1.x, 0
        li      r1.y, 5
        li      r1.z, 0x80000000                ; -0.0: nonzero bits
        bnz     r1, t1                          ; r1.x = 0: not taken
        li      r2.x, 1
t1:     bnz     r1.y, t2                        ; taken
        li      r2.y, 0xbad
t2:     bnz     r1.zyx, t3                      ; lane x of r1.zyx = 0x80000000: taken
        li      r2.z, 0xbad
t3:     li      r2.w, 3
        li      r3.x, 5
loop:   iaddi   r3.x, r3.x, -1
        iaddi   r3.y, r3.y, 2
        bnz     r3.x, loop
        halt

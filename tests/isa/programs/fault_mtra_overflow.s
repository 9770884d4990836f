; mtra past call_depth (16 on tiny): the 17th faults like a call would.
raygen:
        li      r1.x, 0
        li      r2.x, 17
loop:
        mtra    r1.x                            ; pc 2
        iaddi   r2.x, r2.x, -1
        bnz     r2.x, loop
        halt

; mfra: the written lanes of d = the top of the return stack, which it pops; mtra puts
; it back. Return addresses kept on the memory stack this way let recursion go deeper
; than call_depth (16 on tiny): 40 levels, each spilling its own.
raygen:
        li      r2.x, 40
        li      r3.x, 0
        call    recurse
        call    probe                           ; pc 3: returns to pc 4
        halt
probe:  mfra    r4
        mtra    r4.x
        ret
recurse:
        mfra    r5.x
        push    r5
        iaddi   r3.x, r3.x, 1
        iaddi   r2.x, r2.x, -1
        bz      r2.x, bottom
        call    recurse
bottom: pop     r5
        mtra    r5.x
        iaddi   r3.x, r3.x, 100
        ret

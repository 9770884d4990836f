; mtra: pushes lane x of the swizzled a on the return stack; ret goes there.
raygen:
        li      r1, 0
        li      r1.y, 5
        mtra    r1.y                            ; the return address: pc 5
        ret
        li      r2.x, 1                         ; pc 4: skipped
        li      r3.x, 7                         ; pc 5
        halt

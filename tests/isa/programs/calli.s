; calli: calls through the shader table. The runner launches with an empty table, so
; any id faults: id = lane x of the swizzled register (here r1.y = 0).
raygen:
        li      r1.x, 3
        calli   r1.y
        halt

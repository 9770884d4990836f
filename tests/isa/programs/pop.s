; pop: the written lanes of d = the 16 bytes at sp, then sp += 16; lanes outside the
; write mask keep their values (the entry is consumed anyway).
raygen:
        li      r1.x, 0x10
        li      r1.y, 0x11
        li      r1.z, 0x12
        li      r1.w, 0x13
        li      r2, 0x20
        push    r1
        push    r2
        push    r1.yyyy
        li      r3, 0x33
        pop     r3.xz                           ; (0x11, -, 0x11, -)
        li      r4, 0x44
        pop     r4.none                         ; consumes r2's entry, writes nothing
        pop     r5.w                            ; r1's entry: w = 0x13
        halt

; push: sp -= 16 and the swizzled register goes to the stack, raw; pop takes the most
; recent first. The whole stack_bytes (4096 = 256 entries on tiny) can be used.
raygen:
        li      r1.x, 1
        li      r1.y, 2
        li      r1.z, 0x7fc00001                ; raw: no NaN canonicalisation
        li      r1.w, 4
        push    r1
        push    r1.wzyx
        pop     r2                              ; the second push
        pop     r3                              ; the first
        ; fill all 256 entries with 0..255, then pop them back: 255 first, 0 last
        li      r4, 0
fill:   push    r4
        iaddi   r4.x, r4.x, 1
        ilti    r5.x, r4.x, 256
        bnz     r5.x, fill
        pop     r6                              ; 255
        li      r7, 0                           ; sum of the rest
drain:  pop     r8
        iadd    r7.x, r7.x, r8.x
        bnz     r8.x, drain                     ; until the 0 pushed first
        halt

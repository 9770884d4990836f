; bz: taken if lane x of the swizzled register is 0 (raw bits: 0x80000000, -0.0 as a
; float, is not zero).
raygen:
        li      r1.x, 1
        li      r1.y, 0
        li      r1.z, 0x80000000
        bz      r1.y, t1                        ; swizzle: lane x of r1.yyyy = 0: taken
        li      r2.x, 0xbad
t1:     bz      r1, t2                          ; r1.x = 1: not taken
        li      r2.y, 1
t2:     bz      r1.z, t3                        ; 0x80000000: not taken
        li      r2.z, 2
t3:     bz      r1.wzyx, t4                     ; lane x of r1.wzyx = r1.w = 0: taken
        li      r2.w, 0xbad
t4:     ; count down to zero
        li      r3.x, 3
loop:   iaddi   r3.x, r3.x, -1
        iaddi   r3.y, r3.y, 1
        bz      r3.x, done
        bra     loop
done:   halt

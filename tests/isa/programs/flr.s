; flr: floor, exact: floor(-0.5) = -1, floor(+0.5) = +0, floor(-0) = -0, ±inf kept,
; NaN canonical, a negative subnormal is -0 (not -1); modifiers, write mask.
raygen:
        lif     r1.x, -0.5
        lif     r1.y, 0.5
        lif     r1.z, -0.0
        lif     r1.w, -1.25
        flr     r2, r1
        lif     r3.x, 2.75
        lif     r3.y, -inf
        lif     r3.z, inf
        li      r3.w, 0xffc0beef                ; NaN with payload
        flr     r4, r3
        li      r5.x, 0x80000001                ; -subnormal
        lif     r5.y, 8388607.5                 ; 2^23 - 0.5
        lif     r5.z, -8388607.5
        lif     r5.w, 16777216.0                ; 2^24, already an integer
        flr     r6, r5
        li      r7, 0x12121212
        flr     r7.y, -r3.x                     ; floor(-2.75) = -3
        flr     r7.z, |r1|.w                    ; floor(1.25) = 1
        halt

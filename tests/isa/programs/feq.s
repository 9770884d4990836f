; feq: quiet equality: NaN equals nothing (not even itself), +0 == -0 == a subnormal;
; the result is an all-ones / zero mask; modifiers, write mask.
raygen:
        lif     r1.x, 1.0
        lif     r1.y, -0.0
        lif     r1.z, nan
        li      r1.w, 0x00000001                ; subnormal: reads as +0
        lif     r2.x, 1.0
        lif     r2.y, 0.0
        lif     r2.z, nan
        lif     r2.w, -0.0
        feq     r3, r1, r2                      ; (1 == 1, -0 == +0, NaN == NaN, sub == -0)
        lif     r4.x, 2.0
        lif     r4.y, inf
        lif     r4.z, -inf
        feq     r5.x, r1.x, r4.x                ; 1 == 2
        feq     r5.y, r4.y, r4.y                ; inf == inf
        feq     r5.z, r4.y, -r4.z               ; inf == -(-inf)
        feq     r5.w, r4.z, r4.y                ; -inf == inf
        li      r6, 0x5a5a5a5a
        lif     r7.x, -3.0
        lif     r7.y, 3.0
        feq     r6.yz, |r7|.x, r7.y             ; |-3| == 3 in y, z
        halt

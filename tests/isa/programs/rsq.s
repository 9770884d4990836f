; rsq: rcp(sqrt(a)) with two roundings (docs/numbers.md); rsq(+0) = +inf,
; rsq(-0) = -inf, rsq(+inf) = +0, negative -> NaN; modifiers, write mask.
raygen:
        lif     r1.x, 4.0
        lif     r1.y, 0.25
        lif     r1.z, 2.0
        lif     r1.w, 1.00000011920928955078125 ; 1 + 2^-23
        rsq     r2, r1
        lif     r3.y, -0.0
        lif     r3.z, inf
        lif     r3.w, -1.0
        rsq     r4, r3                          ; (+0, -0, inf, -1)
        lif     r5.x, -inf
        li      r5.y, 0x80000001                ; -subnormal: -0, so -inf
        rsq     r6.xy, r5
        lif     r6.zw, 16.0
        rsq     r6.w, |r3|.w                    ; |-1| -> 1; z keeps 16
        halt

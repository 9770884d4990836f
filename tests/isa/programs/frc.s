; frc: a - floor(a), one rounding; in [0, 1] with 1.0 included; frc(-0) = +0;
; frc(±inf) = NaN; modifiers, write mask.
raygen:
        lif     r1.x, 1.25
        lif     r1.y, -1.25
        lif     r1.z, -0.1
        lif     r1.w, -2.98023223876953125e-08  ; -2^-25
        frc     r2, r1
        lif     r3.x, -0.0
        lif     r3.y, inf
        lif     r3.z, -inf
        lif     r3.w, 3.0
        frc     r4, r3
        lif     r5.x, 1e10                      ; an integer in fp32
        lif     r5.y, -0.5
        lif     r5.z, nan
        li      r5.w, 0x80000001                ; -subnormal: -0
        frc     r6, r5
        li      r7, 0x77777777
        frc     r7.xw, -|r1|.x                  ; frc(-1.25) = 0.75
        halt

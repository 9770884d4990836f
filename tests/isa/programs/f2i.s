; f2i: truncation toward zero to int32; saturates at and beyond ±2^31 and for ±inf;
; NaN gives 0; -2^31 is exact; neg/abs apply before the conversion; write mask.
raygen:
        lif     r1.x, 2.7
        lif     r1.y, -2.7
        lif     r1.z, -0.5
        lif     r1.w, nan
        f2i     r2, r1
        lif     r3.x, inf
        lif     r3.y, -inf
        lif     r3.z, 2147483648.0              ; 2^31: saturates
        lif     r3.w, -2147483648.0             ; -2^31: exact
        f2i     r4, r3
        lif     r5.x, 3e9
        lif     r5.y, 2147483520.0              ; the largest fp32 below 2^31
        lif     r5.z, -0.0
        li      r5.w, 0x80000001                ; -subnormal
        f2i     r6, r5
        li      r7, 0x31313131
        lif     r8.x, 7.9
        f2i     r7.x, -r8.x                     ; -7
        f2i     r7.z, -|r3|.x                   ; -inf -> INT32_MIN
        halt

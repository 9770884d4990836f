; lif in fp32: the assembler rounds the literal to fp32, the core rounds that into the
; format: in fp32 that is the input flush (subnormals -> signed zero) and the canonical
; NaN.
raygen:
        lif     r1.x, 0.1                       ; 0x3dcccccd
        lif     r1.y, -2.5
        lif     r1.z, -0.0
        lif     r1.w, -inf
        lif     r2.x, 0x00000001                ; subnormal -> +0
        lif     r2.y, 0x807fffff                ; -subnormal -> -0
        lif     r2.z, 0x7fc00001                ; NaN payload -> 0x7fc00000
        lif     r2.w, 0xff800001                ; -sNaN -> 0x7fc00000
        lif     r3.x, 1e-45                     ; the literal is a subnormal in fp32 -> +0
        lif     r3.y, 3.4028235e38              ; largest finite
        lif     r3.z, 1.00000005960464477539    ; 1 + 2^-24: the assembler's tie -> 1.0
        lif     r3.w, 16777217                  ; an integer literal: 2^24 + 1 -> 2^24
        li      r4, 0x55
        lif     r4.yw, 0.5
        halt

; mov: raw bits move (no rounding, NaN payloads and subnormals kept); swizzle; write
; mask; neg/abs flip or clear the sign bit, but leave the canonical NaN alone.
raygen:
        li      r1.x, 0x3f800000        ; 1.0
        li      r1.y, 0xbfc00000        ; -1.5
        li      r1.z, 0x7fc00001        ; a NaN with a payload
        li      r1.w, 0x00000001        ; the smallest subnormal
        mov     r2, r1                  ; raw: every bit pattern as it was
        mov     r3, r1.wzyx             ; swizzle
        li      r4, 0x11111111
        mov     r4.yw, r1.x             ; write mask: x, z keep 0x11111111
        li      r5.x, 0x00000000        ; +0
        li      r5.y, 0x7fc00000        ; the canonical NaN
        li      r5.z, 0x40000000        ; 2.0
        li      r5.w, 0xc0400000        ; -3.0
        mov     r6, -r5
        mov     r7, |r5|
        mov     r8, -|r5|
        halt

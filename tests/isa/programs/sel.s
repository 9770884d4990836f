; sel: d = a != 0 ? b : c per lane, on raw bits: any nonzero pattern selects b,
; including 0x80000000 (-0.0 as a float) and a NaN.
raygen:
        li      r1.x, 0xffffffff
        li      r1.y, 0
        li      r1.z, 0x80000000
        li      r1.w, 1
        li      r2, 0x0b0b0b0b
        li      r3, 0x0c0c0c0c
        sel     r4, r1, r2, r3
        ; swizzles on all three sources, and a write mask
        li      r5.x, 11
        li      r5.y, 22
        li      r5.z, 33
        li      r5.w, 44
        li      r6.x, 0x7fc00001                ; NaN: nonzero
        li      r7, 0x99999999
        sel     r7.xyz, r6.xyxy, r5.wzyx, r5    ; mask (x, 0, x, -) -> (44, 22, 22, -)
        halt

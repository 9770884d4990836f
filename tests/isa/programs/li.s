; li: the 32-bit immediate, as raw bits, in every written lane (no rounding, no flush).
raygen:
        li      r1, 0x12345678
        li      r2, -1
        li      r3, 0x12121212
        li      r3.xz, 0x00000001               ; a subnormal as a float: kept
        li      r4, 0x7fc0dead                  ; a NaN payload: kept
        li      r5.w, -2147483648
        li      r6.none, 5                      ; no lanes written
        halt

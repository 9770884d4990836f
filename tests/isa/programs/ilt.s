; ilt: signed a < b.
raygen:
        li      r1.x, -1
        li      r1.y, 0x7fffffff
        li      r1.z, 5
        li      r1.w, 0x80000000                ; INT32_MIN
        li      r2.x, 0
        li      r2.y, 0x80000000
        li      r2.z, 5
        li      r2.w, 0x7fffffff
        ilt     r3, r1, r2                      ; (-1 < 0, MAX < MIN, 5 < 5, MIN < MAX)
        li      r4, 0x4c4c4c4c
        ilt     r4.zw, r2.zw, r1.zw             ; (-, -, 5 < 5, MAX < MIN)
        halt

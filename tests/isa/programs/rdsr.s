; rdsr: the special registers pixel, launch, thread, params (by name or index).
raygen:
        rdsr    r1, pixel
        rdsr    r2, launch
        rdsr    r3, thread
        rdsr    r4, params
        li      r5, 0x55
        rdsr    r5.yw, 0                        ; pixel by index, lanes y, w
        halt

; out-of-range access: an address in no segment (between the image and the launch block).
raygen:
        li      r1.x, 0x30000000
        ld      r2, [r1]
        halt

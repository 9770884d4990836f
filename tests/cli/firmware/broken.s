raygen:
        frobnicate r1, r2
        halt

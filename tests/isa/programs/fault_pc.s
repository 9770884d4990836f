; pc: a program without halt runs off the end of its code.
raygen:
        li      r1, 1
        li      r2, 2

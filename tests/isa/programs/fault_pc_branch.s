; pc: a branch to an instruction index past the code.
raygen:
        bra     1000
        halt

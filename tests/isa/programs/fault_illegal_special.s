; illegal instruction: rdsr of a special register that does not exist (0..3 do).
raygen:
        rdsr    r1, 3
        rdsr    r1, 4
        halt

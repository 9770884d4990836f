; illegal instruction: r40 exists in the encoding (6 bits) but not on tiny (32 registers).
raygen:
        li      r31, 1                          ; the last register is fine
        li      r40, 1
        halt

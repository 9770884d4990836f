; illegal instruction: a word whose opcode (bits 6:0) no instruction has.
raygen:
        li      r1, 1
        .insn   0x7f
        halt

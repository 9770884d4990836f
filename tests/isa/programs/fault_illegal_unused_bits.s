; illegal instruction: halt (0x56) with a bit of the dst field (bit 7) set, a field
; halt does not use.
raygen:
        .insn   0xd6
        halt

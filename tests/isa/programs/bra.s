; bra: unconditional, forward (skipping code) and backward (a loop).
raygen:
        bra     forward
        li      r1.x, 0xbad                     ; skipped
forward:
        li      r1.y, 1
        li      r2.x, 4                         ; loop count
        li      r3.x, 0
back:   iaddi   r3.x, r3.x, 3
        iaddi   r2.x, r2.x, -1
        bz      r2.x, out
        bra     back
out:    bra     next                            ; to the very next instruction
next:   li      r1.z, 2
        bra     end
        li      r1.w, 0xbad                     ; skipped
end:    halt

; call: pushes pc + 1 on the return stack and jumps; ret comes back to the instruction
; after the call. Recursion to exactly call_depth (16 on tiny) does not fault.
raygen:
        li      r1.x, 0
        call    sub                             ; r1.x = 1
        iaddi   r1.x, r1.x, 10                  ; runs after the return: 11
        ; recursion 16 deep: each level adds 1 on the way down and 100 on the way up
        li      r2.x, 16
        li      r3.x, 0
        call    recurse
        halt
sub:    li      r1.x, 1
        ret
recurse:
        iaddi   r3.x, r3.x, 1
        iaddi   r2.x, r2.x, -1
        bz      r2.x, bottom
        call    recurse
bottom: iaddi   r3.x, r3.x, 100
        ret

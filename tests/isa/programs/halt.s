; halt: the thread ends; nothing after it runs, even with calls outstanding.
raygen:
        li      r1.x, 1
        call    sub
        li      r1.z, 0xbad                     ; never reached: sub halts
        halt
sub:    li      r1.y, 2
        halt
        li      r1.w, 0xbad

; stack underflow: pop with nothing pushed (one push, two pops).
raygen:
        push    r1
        pop     r2
        pop     r2
        halt

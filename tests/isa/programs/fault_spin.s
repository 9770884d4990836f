; spin: a loop that writes nothing (a bz not taken, a bnz taken back to it). The thread
; faults when it is about to retire one more such branch after as many in a row as the
; code has instructions (5): here the third bz, long before the runner's watchdog.
raygen:
        li      r1.x, 1
        bra     loop                            ; the run of branches starts here
loop:   bz      r1.x, never                     ; not taken
        bnz     r1.x, loop                      ; taken
never:  halt

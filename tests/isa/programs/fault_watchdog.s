; watchdog: an endless loop; the runner sets the limit to 100000 instructions.
raygen:
        li      r1.x, 0
loop:   iaddi   r1.x, r1.x, 1
        bra     loop

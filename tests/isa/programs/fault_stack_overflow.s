; push past the thread's stack_bytes (4096 bytes = 256 pushes on tiny).
raygen:
loop:
        push    r0
        bra     loop

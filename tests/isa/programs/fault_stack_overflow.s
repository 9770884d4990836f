; push past the thread's stack_bytes (16384 bytes = 1024 pushes on tiny).
raygen:
loop:
        push    r0
        bra     loop

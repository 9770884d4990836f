; out-of-range access: the stack segment is reached only by push and pop, even the
; thread's own stack.
raygen:
        push    r1
        li      r1.x, DEVICE_STACK_BASE
        ld      r2, [r1 + 4080]                 ; where the push went (thread 0, 4096 bytes)
        halt

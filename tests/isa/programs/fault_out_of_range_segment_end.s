; out-of-range access: a 16-byte load that starts inside the 160-byte launch block (no
; shader table) and runs past its end.
raygen:
        li      r1.x, DEVICE_LAUNCH_BASE
        ld      r2, [r1 + 144]                  ; the last 16 bytes: fine
        ld      r2, [r1 + 152]
        halt

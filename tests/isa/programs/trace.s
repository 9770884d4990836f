; trace: from the camera (0, 0, 5) straight down -z the ray meets the triangle's
; point (0, 0, 0) = a + 0.25 (b - a) + 0.5 (c - a) at t = 5; pointing away it misses.
raygen:
        lif     r0.xyz, 0.0
        lif     r0.z, 5.0
        lif     r0.w, 0.0
        lif     r1.xy, 0.0
        lif     r1.z, -1.0
        lif     r1.w, inf
        trace   r2, r0, r1
        mov     r3, r1
        mov     r3.z, -r1.z
        trace   r4, r0, r3
        ; a t_max short of the triangle: a miss too
        lif     r1.w, 4.0
        trace   r5, r0, r1
        halt

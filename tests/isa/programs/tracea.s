; tracea: any-hit ray, operands as trace: (t, u, v, triangle) of a hit, or
; (+inf, 0, 0, 0xffffffff). t_min (origin w) and t_max (direction w) bound the hit.
raygen:
        lif     r0.xyz, 0.0
        lif     r0.z, 5.0                       ; origin (0, 0, 5), t_min 0
        lif     r1.xy, 0.0
        lif     r1.z, -1.0
        lif     r1.w, inf                       ; direction -z
        tracea  r2, r0, r1                      ; hits (0, 0, 0) at t = 5
        mov     r3, r0
        lif     r3.w, 6.0                       ; t_min beyond the triangle: miss
        tracea  r4, r3, r1
        mov     r5, r1
        lif     r5.w, 4.0                       ; t_max short of it: miss
        tracea  r6, r0, r5
        lif     r7.xy, 0.25
        lif     r7.z, 5.0
        tracea  r8, r7, r1                      ; (0.25, 0.25, 0): inside, u = 0.3125, v = 0.625
        lif     r7.x, 0.5
        tracea  r11, r7, r1                     ; (0.5, 0.25, 0): past the edge b-c (u + v > 1)
        lif     r9.x, 2.0
        lif     r9.z, 5.0
        li      r10, 0x0a
        tracea  r10.xw, r9, r1                  ; (2, 0, 0) is outside: miss; y, z keep 0x0a
        halt

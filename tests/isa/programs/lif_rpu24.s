; lif in rpu24 (E7M16: 17 significant bits, largest (2 - 2^-16) 2^63, smallest normal
; 2^-62): the fp32 constant rounds into the format.
raygen:
        lif     r1.x, 1.0009765625              ; 1 + 2^-10: exact (as in fp16)
        lif     r1.y, 1.0000076293945312        ; 1 + 2^-17: tie, even -> 1.0
        lif     r1.z, 1.0000228881835938        ; 1 + 3*2^-17: tie, even -> 1 + 2^-15
        lif     r1.w, 1.0000457763671875        ; 1 + 3*2^-16: exact here, 1.0 in fp16
        lif     r2.x, 0.1
        lif     r2.y, 1e20                      ; past the largest finite: inf
        lif     r2.z, 1.8446673704965374e19     ; (2 - 2^-17) 2^63: tie above the largest -> inf
        lif     r2.w, 1.8446603336221196e19     ; (2 - 2^-16) 2^63: the largest, exact
        lif     r3.x, 1e-19                     ; below 2^-62: +0
        lif     r3.y, 2.168404344971009e-19     ; 2^-62: the smallest normal, kept
        lif     r3.z, 3.14159265
        lif     r3.w, 1e-30                     ; normal in fp32, zero in rpu24
        halt

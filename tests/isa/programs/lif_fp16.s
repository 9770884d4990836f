; lif in fp16 (E5M10: 11 significant bits, largest 65504, smallest normal 2^-14): the
; fp32 constant rounds into the format; the register holds it widened to fp32.
raygen:
        lif     r1.x, 1.0009765625              ; 1 + 2^-10: exact
        lif     r1.y, 1.00048828125             ; 1 + 2^-11: tie, even -> 1.0
        lif     r1.z, 1.00146484375             ; 1 + 3*2^-11: tie, even -> 1 + 2^-9
        lif     r1.w, 1.0000457763671875        ; 1 + 3*2^-16: below half an ulp -> 1.0
        lif     r2.x, 0.1                       ; fp16 0x2e66 = 0.0999755859375
        lif     r2.y, 65519.0                   ; below the tie at 65520 -> 65504
        lif     r2.z, 65520.0                   ; tie between 65504 and 65536 (even): inf
        lif     r2.w, -65536.0                  ; -inf
        lif     r3.x, 6.1e-5                    ; below 2^-14 = 6.103515625e-5 after rounding: +0
        lif     r3.y, 6.102025508880615e-05     ; 2^-14 - 2^-26: rounds up to 2^-14, kept
        lif     r3.z, -1e-5                     ; -0
        lif     r3.w, 3.14159265                ; pi -> 3.140625
        halt

; i2f in rpu24 (E7M16: 17 significant bits): integers round to 17 bits.
raygen:
        li      r1.x, 65537                     ; 2^16 + 1: 17 bits, exact
        li      r1.y, 131073                    ; 2^17 + 1: tie, even -> 2^17
        li      r1.z, 131075                    ; 2^17 + 3: tie, even -> 2^17 + 4
        li      r1.w, 16777217
        i2f     r2, r1
        li      r3.x, 0x7fffffff
        li      r3.y, -100000                   ; 0x186a0: 17 bits, exact
        li      r3.z, 100001                    ; 0x186a1: 17 bits, exact
        li      r3.w, 200003                    ; 0x30d43: 18 bits, odd: tie to 200004
        i2f     r4, r3
        halt

; illegal instruction: a source register past the configuration's count; rpu2005 has 16.
raygen:
        add     r15, r1, r15                    ; r15 is the last one
        add     r1, r2, -r16.x
        halt

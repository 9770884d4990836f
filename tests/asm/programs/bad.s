; Two mistakes for the CLI error test.
main:
    rdsr r0, pixel
    mull r1, r0, r0
    add r1, r0

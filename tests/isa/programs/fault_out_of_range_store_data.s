; out-of-range access: .data is read-only for the shaders too (docs/shader-core.md).
        .data
cell:   .word   0
        .text
raygen:
        li      r1.x, cell
        st1     [r1], r2.x
        halt

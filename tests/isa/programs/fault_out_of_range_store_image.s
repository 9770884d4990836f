; out-of-range access: a store to the memory image, which is read-only.
raygen:
        st      [r0 + 16], r1.x
        halt

; shader id: calli with an id past the shader table (the runner's table is empty).
raygen:
        li      r1.z, -1
        calli   r1.zyx
        halt

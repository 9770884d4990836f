; A small shader for the CLI tests and docs/assembler.md: one thread per pixel writes
; (u, v, 0.25, 1) times a tint into the framebuffer. Memory-map symbols come from
; spec/memory_map.toml; the tint and the pixel size from the included file.
.include "gradient_data.s"

.text
main:
    rdsr r0, pixel                          ; (x, y, y * width + x, 0)
    rdsr r1, launch                         ; (width, height, spp, max depth)
    i2f r2.xy, r0                           ; pixel position as floats
    i2f r3.xy, r1
    rcp r3.xy, r3
    mul r2.xy, r2, r3                       ; (u, v) in [0, 1)
    lif r2.z, 0.25
    lif r2.w, 1.0
    li r4.x, tint
    ldf r5, [r4]
    mul r2, r2, r5
    li r6.x, DEVICE_LAUNCH_BASE
    ld1 r6.x, [r6 + LAUNCH_FRAMEBUFFER_AT]  ; address of pixel (0, 0)
    imuli r7.x, r0.z, PIXEL_BYTES
    iadd r6.x, r6, r7
    st [r6], r2
done:
    halt

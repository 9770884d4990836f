; ld: four raw words at address, address + 4, + 8, + 12 (address = lane x of the
; swizzled base register + offset), from the launch block, the memory image and .data.
        .data
words:  .word   0x11111111, 0x22222222, 0x7fc00001, 0x00000001, 0x55555555
        .text
raygen:
        li      r1.x, DEVICE_LAUNCH_BASE
        ld      r2, [r1 + LAUNCH_WIDTH_AT]      ; (width, height, spp, max depth)
        ld      r3, [r1 + LAUNCH_SEED_AT]       ; (seed, framebuffer, shader count, table)
        ld      r4, [r0]                        ; the image header at address 0
        li      r5.y, words
        ld      r6, [r5.y + 4]                  ; base from lane y (swizzle); raw words
        li      r7, 0x77
        ld      r7.xz, [r5.y]                   ; write mask: y, w keep 0x77
        li      r8.x, words + 20
        ld      r9, [r8 - 16]                   ; negative offset
        halt

; Data of gradient.s.
.equ PIXEL_BYTES, FRAMEBUFFER_BYTES_PER_PIXEL

.data
    .align 16
tint:
    .float 1.0, 0.5, 1.0, 1.0

; Whitted ray tracing: the shading model of docs/shading.md, the one the reference
; renderer implements, as firmware for the RPU shader cores. ABI: docs/shader-core.md.
;
; Registers kept by every routine:
;   r15 = (launch block address, ray epsilon (float), max depth (int), 0)
;   r14 = (random stream state, depth of the current ray (int), primary hit's triangle,
;          0 once the state is seeded, else the draws still to skip + 1: see rand)
; Everything else is clobbered by calls; callers push what they need.
;
; Recursion: shade_ray and hit_whitted keep their return addresses on the memory stack
; (mfra/mtra), so the return stack never holds more than FIRMWARE_RETURN_STACK_ENTRIES
; (raygen or hit_whitted -> rand -> permute or hash, below a hit shader's calli) at any depth.
; The memory stack holds raygen's two pushes and the primary ray's shade_ray, then per
; bounce hit_whitted's eight reflection pushes (its return address rides in r9.z) and
; shade_ray's one. The device checks these against the configuration at launch
; (docs/shader-core.md "The shader ABI").
.equ FIRMWARE_RETURN_STACK_ENTRIES, 3
.equ FIRMWARE_STACK_BYTES, 3 * 16
.equ FIRMWARE_STACK_BYTES_PER_DEPTH, 9 * 16
; raygen does selected ray tracing (docs/selection.md): the launch block's select fields.
.equ FIRMWARE_SELECTS, 1
; The stream's state steps as x * 747796405 + 2891336453 (mod 2^32); two steps at once:
; x * 747796405^2 + 2891336453 * (747796405 + 1).
.equ STREAM_MUL2, 4201498105
.equ STREAM_ADD2, 1192405134

.text

; ---------------------------------------------------------------------------------
; raygen: one pixel. spp jittered samples (docs/shading.md section 1), each traced by
; shade_ray; the mean goes to the framebuffer as (r, g, b, 1), or in pass 0 of a
; selected frame as (r, g, b, the key: sample 0's primary triangle).
; r12 = (sample, column, row, n) with n = round(sqrt(spp)); r13 = colour sum.
raygen:
        li      r15.x, DEVICE_LAUNCH_BASE
        ld1     r0.x, [r15 + LAUNCH_SCENE_AT]
        ld1f    r15.y, [r0 + SCENE_RECORD_RAY_EPSILON_AT]
        ld1     r15.z, [r15 + LAUNCH_MAX_DEPTH_AT]
        li      r15.w, 0
        ld1     r0.x, [r15 + LAUNCH_SELECT_BLOCK_AT]
        ilti    r0.x, r0.x, 2
        bnz     r0.x, every_pixel       ; block 0 or 1: every pixel traced
        call    select                  ; returns if this pixel is traced
every_pixel:
        li      r12, 0
        li      r12.w, 1                ; n = 1 for one sample, without the sfu
        li      r13, 0
        ld1     r0.x, [r15 + LAUNCH_SPP_AT]
        ilti    r0.y, r0.x, 2
        bnz     r0.y, sample_loop
        i2f     r0.y, r0.x
        sqrt    r0.y, r0.y
        lif     r0.z, 0.5
        add     r0.y, r0.y, r0.z
        flr     r0.y, r0.y
        f2i     r12.w, r0.y
sample_loop:
        ; the sample's stream, seeded at its first draw (rand)
        mov     r14.x, r12.x
        li      r14.w, 1
        ; r1.xy = the sample's position in the pixel
        ld1     r0.x, [r15 + LAUNCH_SPP_AT]
        ilti    r0.y, r0.x, 2
        bz      r0.y, jitter
        lif     r1.xy, 0.5
        bra     have_offset
jitter:
        call    rand
        mov     r1.x, r11.x
        call    rand
        mov     r1.y, r11.x
        imul    r0.y, r12.w, r12.w
        ieq     r0.y, r0.y, r0.x
        bz      r0.y, have_offset       ; spp not square: uniform jitter
        i2f     r2.xy, r12.yz           ; (column, row)
        add     r1.xy, r1, r2
        i2f     r2.x, r12.w
        rcp     r2.x, r2.x
        mul     r1.xy, r1, r2.x
have_offset:
        ; the lens sample: two draws a pinhole camera discards, skipped to keep the stream
        ; in step: two steps of the state at once, or two more for its seeding to skip
        bnz     r14.w, lens_unseeded
        imuli   r14.x, r14.x, STREAM_MUL2
        iaddi   r14.x, r14.x, STREAM_ADD2
        bra     lens_skipped
lens_unseeded:
        li      r14.w, 3
lens_skipped:
        ; direction = forward + (2 px/width - 1) right + (1 - 2 py/height) up
        rdsr    r0, pixel
        i2f     r0.xy, r0
        add     r1.xy, r1, r0
        rdsr    r0, launch
        i2f     r0.xy, r0
        rcp     r0.xy, r0
        mul     r1.xy, r1, r0
        add     r1.xy, r1, r1
        lif     r0.z, 1.0
        add     r1.x, r1.x, -r0.z
        add     r1.y, r0.z, -r1.y
        ldf     r2.xyz, [r15 + LAUNCH_FORWARD_AT]
        ldf     r3.xyz, [r15 + LAUNCH_RIGHT_AT]
        ldf     r4.xyz, [r15 + LAUNCH_UP_AT]
        mad     r2.xyz, r3, r1.x, r2
        mad     r2.xyz, r4, r1.y, r2
        dp3     r3.x, r2, r2
        rsq     r3.x, r3.x
        mul     r1.xyz, r2, r3.x
        lif     r1.w, inf
        ldf     r0.xyz, [r15 + LAUNCH_ORIGIN_AT]
        mov     r0.w, r15.w
        li      r14.y, 0
        push    r12
        push    r13
        call    shade_ray
        pop     r13
        pop     r12
        bnz     r12.x, keyed
        mov     r13.w, r14.z            ; the pixel's key
keyed:
        add     r13.xyz, r13, r0
        ; next sample: column + 1, wrapping to the next row after n
        iaddi   r12.x, r12.x, 1
        iaddi   r12.y, r12.y, 1
        ieq     r0.x, r12.y, r12.w
        bz      r0.x, same_row
        li      r12.y, 0
        iaddi   r12.z, r12.z, 1
same_row:
        ld1     r0.x, [r15 + LAUNCH_SPP_AT]
        ilt     r0.y, r12.x, r0.x
        bnz     r0.y, sample_loop
        ilti    r0.y, r0.x, 2
        bnz     r0.y, mean_done         ; one sample is its own mean
        i2f     r0.x, r0.x
        rcp     r0.x, r0.x
        mul     r13.xyz, r13, r0.x
mean_done:
        ld1     r0.x, [r15 + LAUNCH_SELECT_BLOCK_AT]
        ilti    r0.x, r0.x, 2
        ld1     r0.y, [r15 + LAUNCH_SELECT_PASS_AT]
        or      r0.x, r0.x, r0.y
        bz      r0.x, store_pixel       ; pass 0 keeps the key in alpha
        lif     r13.w, 1.0
store_pixel:
        ld1     r0.x, [r15 + LAUNCH_FRAMEBUFFER_AT]
        rdsr    r1, pixel
        shli    r1.z, r1.z, 4           ; FRAMEBUFFER_BYTES_PER_PIXEL = 16
        iadd    r0.x, r0.x, r1.z
        st      [r0], r13
        halt

; ---------------------------------------------------------------------------------
; select: selected ray tracing (docs/selection.md), a frame of two launches. The
; corners of the B x B blocks are the pixels whose column is a multiple of B or the
; last one, and whose row is too. Pass 0 traces the corners only. Pass 1 copies the
; corners from pass 0's framebuffer and fills every other pixel from the four corners
; of its block: bilinearly when they agree, by tracing it when they disagree (their
; keys, or their colours by more than the threshold in a channel). Returns when this
; pixel is to be traced, else halts. Clobbers r0..r13.
select:
        rdsr    r1, pixel               ; (x, y, index, 0)
        rdsr    r2, launch              ; (width, height, -, -)
        ld1     r0.x, [r15 + LAUNCH_SELECT_BLOCK_AT]
        ld1     r0.y, [r15 + LAUNCH_SELECT_RECIPROCAL_AT]
        imulhu  r3.xy, r1, r0.y         ; (x, y) / B
        imul    r3.xy, r3, r0.x         ; (x0, y0): the block's first corner
        iaddi   r5.xy, r2, -1           ; the last column and row
        iadd    r4.xy, r3, r0.x
        ilt     r6.xy, r4, r5
        sel     r4.xy, r6, r4, r5       ; (x1, y1) = min((x0, y0) + B, last): its far corner
        ieq     r6.xy, r1, r3
        ieq     r7.xy, r1, r5
        or      r6.xy, r6, r7
        and     r6.x, r6.x, r6.y        ; a corner
        ld1     r0.z, [r15 + LAUNCH_SELECT_PASS_AT]
        bnz     r0.z, select_fill
        bz      r6.x, select_skip
        ret                             ; pass 0: trace the corners
select_skip:
        halt
select_fill:
        ld1     r7.x, [r15 + LAUNCH_SELECT_CORNERS_AT]
        bz      r6.x, select_block
        shli    r8.x, r1.z, 4           ; FRAMEBUFFER_BYTES_PER_PIXEL = 16
        iadd    r8.x, r8.x, r7.x
        ld      r9, [r8]                ; the corner as pass 0 traced it, raw
        lif     r9.w, 1.0
        bra     select_store
select_block:
        imul    r8.x, r3.y, r2.x
        imul    r8.y, r4.y, r2.x
        iadd    r8.z, r8.x, r4.x
        iadd    r8.w, r8.y, r4.x
        iadd    r8.x, r8.x, r3.x
        iadd    r8.y, r8.y, r3.x        ; the corners' pixels (x0 y0, x0 y1, x1 y0, x1 y1)
        shli    r8, r8, 4               ; FRAMEBUFFER_BYTES_PER_PIXEL = 16
        iadd    r8, r8, r7.x
        ldf     r9.xyz, [r8.x]
        ldf     r10.xyz, [r8.y]
        ldf     r11.xyz, [r8.z]
        ldf     r12.xyz, [r8.w]
        ld1     r5.x, [r8.x + 12]       ; their keys, from alpha
        ld1     r5.y, [r8.y + 12]
        ld1     r5.z, [r8.z + 12]
        ld1     r5.w, [r8.w + 12]
        li      r7.y, 0                 ; r5 holds triangles, not yet materials
select_keys:
        ieq     r6, r5, r5.x
        and     r6.x, r6.x, r6.y
        and     r6.x, r6.x, r6.z
        and     r6.x, r6.x, r6.w
        bnz     r6.x, select_colours    ; one triangle (or none): one material
        bnz     r7.y, select_trace      ; the materials differ
        ld1     r0.x, [r15 + LAUNCH_SELECT_KEY_AT]
        bnz     r0.x, select_trace      ; SELECT_KEY_PRIMITIVE: the triangles differ
        li      r0, -1
        ieq     r6, r5, r0              ; the corners that hit nothing ...
        sel     r5, r6, r15.w, r5       ; ... look up triangle 0 (one corner hit, so there is one)
        imuli   r5, r5, TRIANGLE_BYTES
        ld1     r0.x, [r15 + LAUNCH_TRIANGLES_AT]
        iadd    r5, r5, r0.x
        ld1     r5.x, [r5.x + TRIANGLE_MATERIAL_AT]
        ld1     r5.y, [r5.y + TRIANGLE_MATERIAL_AT]
        ld1     r5.z, [r5.z + TRIANGLE_MATERIAL_AT]
        ld1     r5.w, [r5.w + TRIANGLE_MATERIAL_AT]
        sel     r5, r6, r6, r5          ; a miss is its own material, 0xffffffff
        li      r7.y, 1
        bra     select_keys
select_colours:
        min     r0.xyz, r9, r10
        min     r0.xyz, r0, r11
        min     r0.xyz, r0, r12
        max     r6.xyz, r9, r10
        max     r6.xyz, r6, r11
        max     r6.xyz, r6, r12
        add     r6.xyz, r6, -r0
        max     r6.x, r6.x, r6.y
        max     r6.x, r6.x, r6.z        ; the colours' largest spread in a channel
        ld1f    r0.w, [r15 + LAUNCH_SELECT_THRESHOLD_AT]
        fle     r6.x, r6.x, r0.w
        bz      r6.x, select_trace      ; over the threshold (or NaN)
        isub    r6.xy, r1, r3
        isub    r0.xy, r4, r3
        i2f     r6.xy, r6
        i2f     r0.xy, r0
        lif     r0.z, 1.0
        max     r0.xy, r0, r0.z         ; a one-pixel-wide last block: t = 0
        rcp     r0.xy, r0
        mul     r6.xy, r6, r0           ; (tx, ty)
        add     r11.xyz, r11, -r9
        mad     r9.xyz, r11, r6.x, r9   ; the top edge at tx
        add     r12.xyz, r12, -r10
        mad     r10.xyz, r12, r6.x, r10 ; the bottom edge at tx
        add     r10.xyz, r10, -r9
        mad     r9.xyz, r10, r6.y, r9
        lif     r9.w, 1.0
select_store:
        ld1     r0.x, [r15 + LAUNCH_FRAMEBUFFER_AT]
        shli    r8.x, r1.z, 4           ; FRAMEBUFFER_BYTES_PER_PIXEL = 16
        iadd    r0.x, r0.x, r8.x
        st      [r0], r9
        halt
select_trace:
        ret

; ---------------------------------------------------------------------------------
; shade_ray: r0 = (origin, t_min), r1 = (direction, t_max) -> r0.xyz = colour.
; A hit calls its material's shader through the shader table with
; r0, r1 as given, r2 = hit record (t, u, v, triangle), r4.x = material address,
; r5 = triangle record (vertex a, b, c, material).
shade_ray:
        trace   r2, r0, r1
        bnz     r14.y, shade_hit        ; a secondary ray
        mov     r14.z, r2.w             ; the primary ray's triangle, the pixel's key
shade_hit:
        iaddi   r3.x, r2.w, 1
        bz      r3.x, shade_miss        ; triangle 0xffffffff: a miss
        ld1     r3.x, [r15 + LAUNCH_TRIANGLES_AT]
        imuli   r4.x, r2.w, TRIANGLE_BYTES
        iadd    r3.x, r3.x, r4.x
        ld      r5, [r3]
        ld1     r4.x, [r15 + LAUNCH_MATERIALS_AT]
        imuli   r6.x, r5.w, MATERIAL_BYTES
        iadd    r4.x, r4.x, r6.x
        ld1     r6.x, [r4 + MATERIAL_SHADER_AT]
        mfra    r7.x                    ; the hit shader may call shade_ray again
        push    r7
        calli   r6.x
        pop     r7
        mtra    r7.x
        ret
shade_miss:
        call    miss
        ret

; miss: r0.xyz = the scene's background.
miss:
        ld1     r3.x, [r15 + LAUNCH_SCENE_AT]
        ldf     r0.xyz, [r3 + SCENE_RECORD_BACKGROUND_AT]
        ret

; ---------------------------------------------------------------------------------
; hit_whitted: docs/shading.md sections 3 and 4.
; Live: r1 = d, r3 = colour, r4 = (material, entering mask), r6 = (P, where a shadow
; ray ends per unit of distance), r7 = (P off the surface on Ng's side, 0), r12 = Ng,
; r13 = N.
hit_whitted:
        ld1     r7.x, [r15 + LAUNCH_POSITIONS_AT]
        shli    r8.xyz, r5, 4           ; VERTEX_POSITION_BYTES = 16
        iadd    r8.xyz, r8, r7.x
        ldf     r9.xyz, [r8.x]
        ldf     r10.xyz, [r8.y]
        ldf     r11.xyz, [r8.z]
        add     r10.xyz, r10, -r9       ; p1 - p0
        add     r11.xyz, r11, -r9       ; p2 - p0
        mad     r6.xyz, r10, r2.y, r9   ; P = p0 + u (p1 - p0) + v (p2 - p0): on the
        mad     r6.xyz, r11, r2.z, r6   ; triangle's plane to rounding, however far the ray came
        max     r12.x, |r10|.x, |r10|.y ; each edge scaled by the power of two that brings
        max     r12.x, r12.x, |r10|.z   ; its largest component into [1, 2), so that the
        max     r12.y, |r11|.x, |r11|.y ; cross product cannot overflow a narrow format
        max     r12.y, r12.y, |r11|.z
        andi    r12.xy, r12, 0x7f800000 ; 2^e: the largest component's exponent
        li      r12.z, 0x7f000000
        isub    r12.xy, r12.z, r12      ; 2^-e: exact, without the sfu
        mul     r10.xyz, r10, r12.x
        mul     r11.xyz, r11, r12.y
        mul     r12.xyz, r10.zxy, r11.yzx
        mad     r8.xyz, r10.yzx, r11.zxy, -r12
        call    unit
        mov     r12.xyz, r8             ; Ng
        mov     r13.xyz, r12            ; N = Ng unless the scene has vertex normals
        ld1     r7.x, [r15 + LAUNCH_NORMALS_AT]
        bz      r7.x, normals_done
        shli    r8.xyz, r5, 4           ; VERTEX_NORMAL_BYTES = 16
        iadd    r8.xyz, r8, r7.x
        ldf     r9.xyz, [r8.x]
        ldf     r10.xyz, [r8.y]
        ldf     r11.xyz, [r8.z]
        lif     r7.x, 1.0
        add     r7.x, r7.x, -r2.y
        add     r7.x, r7.x, -r2.z       ; w = 1 - u - v
        mul     r9.xyz, r9, r7.x
        mad     r9.xyz, r10, r2.y, r9
        mad     r9.xyz, r11, r2.z, r9   ; w n0 + u n1 + v n2
        dp3     r10.x, r9, r9
        flt     r10.y, r15.w, r10.x
        bz      r10.y, normals_done     ; a zero blend keeps Ng
        rsq     r10.x, r10.x
        mul     r13.xyz, r9, r10.x
        dp3     r10.x, r13, r12
        flt     r10.x, r10.x, r15.w
        bz      r10.x, normals_done
        mov     r13.xyz, -r13           ; turned to Ng's side
normals_done:
        dp3     r10.x, r1, r12
        flt     r4.y, r10.x, r15.w      ; entering: d . Ng < 0
        bnz     r4.y, facing
        mov     r12.xyz, -r12           ; leaving: both normals face the viewer
        mov     r13.xyz, -r13
facing:
        mov     r8.xyz, r12
        call    offset
        mov     r7.xyz, r8              ; P off the surface on Ng's side
        mov     r7.w, r15.w
        ld1     r9.x, [r15 + LAUNCH_SCENE_AT]
        ld1     r9.x, [r9.x + SCENE_RECORD_RAY_OFFSET_SHIFT_AT]
        iaddi   r9.x, r9.x, 104         ; 127 - 23 + (23 - M): the fp32 exponent of 2^-M
        shli    r9.x, r9.x, 23          ; 2^-M, the format's relative precision
        li      r9.y, RAY_OFFSET_ULPS
        i2f     r9.y, r9.y
        lif     r6.w, 1.0
        mad     r6.w, r9.x, -r9.y, r6.w ; 1 - ulps 2^-M: where a shadow ray ends, per unit of distance
        ldf     r3.xyz, [r4 + MATERIAL_AMBIENT_AT]

        ; lights: r5 = (lights left, light address)
        ld1     r5.x, [r15 + LAUNCH_SCENE_AT]
        ld1     r5.x, [r5 + SCENE_RECORD_LIGHT_COUNT_AT]
        ld1     r5.y, [r15 + LAUNCH_LIGHTS_AT]
light_loop:
        bz      r5.x, lights_done
        ld1     r0.x, [r5.y + LIGHT_KIND_AT]
        iaddi   r0.y, r0.x, -LIGHT_KIND_DIRECTIONAL
        bnz     r0.y, positional
        ldf     r8.xyz, [r5.y + LIGHT_DIRECTION_AT]
        mov     r8.xyz, -r8             ; L = -direction
        lif     r8.w, inf               ; distance
        bra     have_l
positional:
        ldf     r9.xyz, [r5.y + LIGHT_POSITION_AT]
        iaddi   r0.y, r0.x, -LIGHT_KIND_AREA
        bnz     r0.y, point
        call    rand                    ; a point of the rectangle
        ldf     r10.xyz, [r5.y + LIGHT_EDGE_U_AT]
        mad     r9.xyz, r10, r11.x, r9
        call    rand
        ldf     r10.xyz, [r5.y + LIGHT_EDGE_V_AT]
        mad     r9.xyz, r10, r11.x, r9
point:
        add     r8.xyz, r9, -r6
        call    unit                    ; L, distance
have_l:
        dp3     r9.x, r13, r8           ; N . L
        fle     r0.y, r9.x, r15.w
        bnz     r0.y, next_light
        dp3     r9.y, r12, r8           ; Ng . L
        fle     r0.y, r9.y, r15.w
        bnz     r0.y, next_light
        mul     r0.y, r8.w, r6.w
        add     r8.w, r8.w, -r15.y
        min     r8.w, r8.w, r0.y        ; shadow ray over (0, the nearer of distance - eps and that)
        tracea  r0, r7, r8
        iaddi   r0.w, r0.w, 1
        bnz     r0.w, next_light        ; blocked
        add     r10.x, r9.x, r9.x
        mul     r2.xyz, r13, r10.x
        add     r2.xyz, r2, -r8         ; R = 2 (N . L) N - L
        dp3     r10.x, r2, -r1          ; R . V
        mov     r2.w, r15.w             ; specular = 0 unless R . V > 0
        flt     r0.y, r15.w, r10.x
        bz      r0.y, no_specular
        ld1f    r10.y, [r4 + MATERIAL_SHININESS_AT]
        call    pow
        mov     r2.w, r10.x
no_specular:
        ldf     r10.xyz, [r4 + MATERIAL_DIFFUSE_AT]
        mul     r10.xyz, r10, r9.x
        ldf     r11.xyz, [r4 + MATERIAL_SPECULAR_AT]
        mad     r10.xyz, r11, r2.w, r10
        ldf     r11.xyz, [r5.y + LIGHT_COLOR_AT]
        mad     r3.xyz, r11, r10, r3
next_light:
        iaddi   r5.x, r5.x, -1
        iaddi   r5.y, r5.y, LIGHT_BYTES
        bra     light_loop
lights_done:
        ilt     r0.x, r14.y, r15.z
        bz      r0.x, whitted_done      ; depth >= max depth: local shading only
        mfra    r9.z                    ; kept with r9 while the secondary rays recurse
        ld1f    r9.x, [r4 + MATERIAL_REFLECTANCE_AT]
        ld1f    r9.y, [r4 + MATERIAL_TRANSMITTANCE_AT]
        flt     r0.x, r15.w, r9.x
        bz      r0.x, no_reflection
        dp3     r10.x, r1, r13
        add     r10.x, r10.x, r10.x
        mul     r11.xyz, r13, r10.x
        add     r11.xyz, r1, -r11       ; d - 2 (d . N) N
        push    r1
        push    r3
        push    r4
        push    r6
        push    r7
        push    r9
        push    r12
        push    r13
        mov     r0, r7
        mov     r1.xyz, r11
        lif     r1.w, inf
        iaddi   r14.y, r14.y, 1
        call    shade_ray
        iaddi   r14.y, r14.y, -1
        mov     r8.xyz, r0
        pop     r13
        pop     r12
        pop     r9
        pop     r7
        pop     r6
        pop     r4
        pop     r3
        pop     r1
        mad     r3.xyz, r8, r9.x, r3    ; + kr trace(reflected)
no_reflection:
        flt     r0.x, r15.w, r9.y
        bz      r0.x, secondary_done
        ld1f    r10.x, [r4 + MATERIAL_IOR_AT]
        rcp     r10.y, r10.x
        sel     r10.z, r4.y, r10.y, r10.x   ; eta = entering ? 1/ior : ior
        dp3     r10.w, r1, -r13             ; cos_i = -d . N
        lif     r11.x, 1.0
        mad     r11.y, -r10.w, r10.w, r11.x ; 1 - cos_i^2
        mul     r11.z, r10.z, r10.z
        mul     r11.y, r11.z, r11.y
        add     r11.y, r11.x, -r11.y        ; k
        flt     r0.x, r11.y, r15.w
        bz      r0.x, refract
        dp3     r10.x, r1, r13              ; total internal reflection: kt goes to the mirror ray
        add     r10.x, r10.x, r10.x
        mul     r11.xyz, r13, r10.x
        add     r1.xyz, r1, -r11
        mov     r0, r7
        bra     transmitted
refract:
        sqrt    r11.y, r11.y
        mul     r11.z, r10.z, r10.w
        add     r11.z, r11.z, -r11.y        ; eta cos_i - sqrt(k)
        mul     r8.xyz, r13, r11.z
        mad     r8.xyz, r1, r10.z, r8       ; eta d + (eta cos_i - sqrt(k)) N
        dp3     r11.x, r8, r8
        rsq     r11.x, r11.x
        mul     r1.xyz, r8, r11.x
        mov     r8.xyz, -r12
        call    offset
        mov     r0.xyz, r8                  ; from P off the surface on the far side
        mov     r0.w, r15.w
transmitted:
        push    r3
        push    r9
        lif     r1.w, inf
        iaddi   r14.y, r14.y, 1
        call    shade_ray
        iaddi   r14.y, r14.y, -1
        pop     r9
        pop     r3
        mad     r3.xyz, r0, r9.y, r3        ; + kt trace(transmitted)
secondary_done:
        mtra    r9.z
whitted_done:
        mov     r0.xyz, r3
        ret

; ---------------------------------------------------------------------------------
; offset: r8.xyz = P (r6.xyz) moved off its surface along the unit normal r8.xyz, robust
; in the configured format (docs/shading.md "Leaving a surface", spec/memory_map.toml
; [ray_offset]): each coordinate by RAY_OFFSET_ULPS of the format's ulps there times the
; normal's component, an integer add on its bits (one ulp is bit s = 23 - M of the fp32
; pattern); a coordinate under ray_epsilon x 2^M / RAY_OFFSET_ULPS, where that would move
; it less, by ray_epsilon times the component. Clobbers r10, r11.
offset:
        ld1     r11.w, [r15 + LAUNCH_SCENE_AT]
        ld1     r11.w, [r11.w + SCENE_RECORD_RAY_OFFSET_SHIFT_AT]
        li      r10.w, RAY_OFFSET_ULPS
        i2f     r10.w, r10.w
        mul     r11.xyz, r8, r10.w      ; n ulps
        f2i     r11.xyz, r11            ; whole ulps, toward zero
        shl     r11.xyz, r11, r11.w     ; as steps of the fp32 pattern
        srai    r10.xyz, r6, 31         ; -1 where P < 0, where a step up the pattern
        xor     r11.xyz, r11, r10       ; moves it down: the steps negated there
        isub    r11.xyz, r11, r10
        iadd    r11.xyz, r6, r11
        mad     r8.xyz, r8, r15.y, r6   ; P + ray_epsilon n
        mul     r10.xyz, |r6|, r10.w    ; |P| ulps
        li      r10.w, 150              ; 127 + 23: the fp32 exponent of 2^M is 150 - (23 - M)
        isub    r10.w, r10.w, r11.w
        shli    r10.w, r10.w, 23        ; 2^M, exact
        mul     r10.w, r10.w, r15.y     ; ray_epsilon 2^M
        flt     r10.xyz, r10, r10.w     ; |P| < ray_epsilon 2^M / ulps
        sel     r8.xyz, r10, r8, r11
        ret

; ---------------------------------------------------------------------------------
; unit: r8.xyz = r8.xyz / |r8.xyz| and r8.w = |r8.xyz|. The vector is first scaled by
; the power of two that brings its largest component into [1, 2) (exact, built from the
; exponent bits), so that its squared length neither overflows nor flushes in a narrow
; format (fp16 squares overflow at 256); one rsq then gives both results. Clobbers r9.
unit:
        max     r9.x, |r8|.x, |r8|.y
        max     r9.x, r9.x, |r8|.z
        andi    r9.x, r9.x, 0x7f800000  ; 2^e: the largest component's exponent
        li      r9.y, 0x7f000000
        isub    r9.y, r9.y, r9.x        ; 2^-e: exact, without the sfu
        mul     r8.xyz, r8, r9.y
        dp3     r9.z, r8, r8            ; in [1, 12)
        rsq     r9.w, r9.z
        mul     r8.xyz, r8, r9.w
        mul     r9.z, r9.z, r9.w        ; |v| 2^-e = (v . v) / sqrt(v . v)
        mul     r8.w, r9.z, r9.x
        ret

; ---------------------------------------------------------------------------------
; rand: r11.x = the next number of the stream in [0, 1) (docs/shading.md section 1);
; steps r14.x. Clobbers r11. A sample's stream starts at h(seed ^ h(pixel ^ h(sample))):
; until its first draw r14.x holds the sample and r14.w the draws to skip + 1, so a
; sample that draws nothing (one sample a pixel, a pinhole camera, point lights) pays
; for no hashing.
rand:
        bnz     r14.w, rand_seed
rand_draw:
        mov     r11.x, r14.x
        imuli   r14.x, r14.x, 747796405
        iaddi   r14.x, r14.x, 2891336453
        call    permute                 ; of the old state
        shri    r11.x, r11.x, 9
        ori     r11.x, r11.x, 0x3f800000    ; 1.f with the top 23 bits as fraction
        lif     r11.z, 1.0
        add     r11.x, r11.x, -r11.z
        ret
rand_seed:
        mov     r11.x, r14.x
        call    hash
        rdsr    r11.z, pixel
        xor     r11.x, r11.x, r11.z
        call    hash
        ld1     r11.z, [r15 + LAUNCH_SEED_AT]
        xor     r11.x, r11.x, r11.z
        call    hash
        ilti    r11.z, r14.w, 3
        bnz     r11.z, rand_seeded
        imuli   r11.x, r11.x, STREAM_MUL2     ; the two draws skipped
        iaddi   r11.x, r11.x, STREAM_ADD2
rand_seeded:
        mov     r14.x, r11.x
        li      r14.w, 0
        bra     rand_draw

; hash: r11.x = h(r11.x) = permute(r11.x * 747796405 + 2891336453), then falls
; through into permute: r11.x = PCG's RXS-M-XS permutation of r11.x. Clobber r11.y.
hash:
        imuli   r11.x, r11.x, 747796405
        iaddi   r11.x, r11.x, 2891336453
permute:
        shri    r11.y, r11.x, 28
        iaddi   r11.y, r11.y, 4
        shr     r11.y, r11.x, r11.y
        xor     r11.y, r11.y, r11.x
        imuli   r11.y, r11.y, 277803737
        shri    r11.x, r11.y, 22
        xor     r11.x, r11.x, r11.y
        ret

; pow: r10.x = r10.x ^ r10.y for 0 < r10.x <= 1 and r10.y >= 0, as exp2(y log2 x):
; log2 by x = m 2^e, m in [sqrt(1/2), sqrt(2)), log2 m = (2/ln 2) atanh((m-1)/(m+1))
; to t^9 (error < 1e-9); exp2 by 2^i 2^(f - 1/2) sqrt(2), the Taylor series of
; 2^g to g^6 (error < 2e-7). Clobbers r10, r11.
pow:
        shri    r10.z, r10.x, 23
        iaddi   r10.z, r10.z, -127      ; e
        andi    r10.w, r10.x, 0x007fffff
        ori     r10.w, r10.w, 0x3f800000    ; m in [1, 2)
        lif     r11.x, 1.41421356
        fle     r11.y, r11.x, r10.w
        bz      r11.y, pow_reduced
        lif     r11.x, 0.5
        mul     r10.w, r10.w, r11.x
        iaddi   r10.z, r10.z, 1
pow_reduced:
        i2f     r10.z, r10.z
        lif     r11.x, 1.0
        add     r11.y, r10.w, -r11.x
        add     r11.z, r10.w, r11.x
        rcp     r11.z, r11.z
        mul     r11.y, r11.y, r11.z     ; t = (m - 1) / (m + 1)
        mul     r11.z, r11.y, r11.y     ; t^2
        lif     r11.w, 0.3205988979753252   ; 2 / (9 ln 2)
        lif     r11.x, 0.41219858311113244  ; 2 / (7 ln 2)
        mad     r11.w, r11.w, r11.z, r11.x
        lif     r11.x, 0.5770780163555854   ; 2 / (5 ln 2)
        mad     r11.w, r11.w, r11.z, r11.x
        lif     r11.x, 0.9617966939259756   ; 2 / (3 ln 2)
        mad     r11.w, r11.w, r11.z, r11.x
        lif     r11.x, 2.8853900817779268   ; 2 / ln 2
        mad     r11.w, r11.w, r11.z, r11.x
        mul     r11.w, r11.w, r11.y     ; log2 m
        add     r10.z, r10.z, r11.w     ; log2 x
        mul     r10.z, r10.z, r10.y     ; y = n log2 x <= 0
        lif     r11.x, -126.0
        max     r10.z, r10.z, r11.x
        flr     r10.w, r10.z            ; i
        add     r10.z, r10.z, -r10.w
        lif     r11.x, 0.5
        add     r10.z, r10.z, -r11.x    ; g = y - i - 1/2
        lif     r11.w, 0.00015403530393381606   ; ln2^6 / 6!
        lif     r11.x, 0.0013333558146428443    ; ln2^5 / 5!
        mad     r11.w, r11.w, r10.z, r11.x
        lif     r11.x, 0.009618129107628477     ; ln2^4 / 4!
        mad     r11.w, r11.w, r10.z, r11.x
        lif     r11.x, 0.05550410866482158      ; ln2^3 / 3!
        mad     r11.w, r11.w, r10.z, r11.x
        lif     r11.x, 0.2402265069591007       ; ln2^2 / 2!
        mad     r11.w, r11.w, r10.z, r11.x
        lif     r11.x, 0.6931471805599453       ; ln 2
        mad     r11.w, r11.w, r10.z, r11.x
        lif     r11.x, 1.0
        mad     r11.w, r11.w, r10.z, r11.x      ; 2^g
        f2i     r10.w, r10.w
        iaddi   r10.w, r10.w, 127
        shli    r10.w, r10.w, 23        ; 2^i as fp32 bits
        mul     r11.w, r11.w, r10.w
        lif     r11.x, 1.41421356
        mul     r10.x, r11.w, r11.x
        ret

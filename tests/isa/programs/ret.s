; ret: pops the top of the return stack: nested calls return in LIFO order. Each
; routine appends a digit to r1.x (r1.x = r1.x * 16 + digit).
raygen:
        li      r1.x, 0
        call    a
        imuli   r1.x, r1.x, 16
        iaddi   r1.x, r1.x, 0xf                 ; back in raygen last
        halt
a:      imuli   r1.x, r1.x, 16
        iaddi   r1.x, r1.x, 1
        call    b
        imuli   r1.x, r1.x, 16
        iaddi   r1.x, r1.x, 4                   ; back in a
        ret
b:      imuli   r1.x, r1.x, 16
        iaddi   r1.x, r1.x, 2
        call    c
        imuli   r1.x, r1.x, 16
        iaddi   r1.x, r1.x, 3                   ; back in b
        ret
c:      ret                                     ; returns at once

; call-depth overflow: 17 nested calls, each from its own call site, so the pc in the
; message shows which call found the 16-entry return stack (tiny's call_depth) full:
; the 17th, in f16.
raygen:
        call    f1                              ; pc 0: the 1st call
        halt
f1:     call    f2                              ; pc 2: call number 2
        ret
f2:     call    f3                              ; pc 4: call number 3
        ret
f3:     call    f4                              ; pc 6: call number 4
        ret
f4:     call    f5                              ; pc 8: call number 5
        ret
f5:     call    f6                              ; pc 10: call number 6
        ret
f6:     call    f7                              ; pc 12: call number 7
        ret
f7:     call    f8                              ; pc 14: call number 8
        ret
f8:     call    f9                              ; pc 16: call number 9
        ret
f9:     call    f10                             ; pc 18: call number 10
        ret
f10:     call    f11                            ; pc 20: call number 11
        ret
f11:     call    f12                            ; pc 22: call number 12
        ret
f12:     call    f13                            ; pc 24: call number 13
        ret
f13:     call    f14                            ; pc 26: call number 14
        ret
f14:     call    f15                            ; pc 28: call number 15
        ret
f15:     call    f16                            ; pc 30: call number 16
        ret
f16:     call    f17                            ; pc 32: call number 17
        ret
f17:     call    f18                            ; pc 34: call number 18
        ret
f18:     ret

; A shader that never halts but writes on every trip (a counter), so that only the
; watchdog's count stops it; tests/cli/firmware/runaway.s writes nothing and is stopped
; at once (the spin fault).
raygen:
count:
        iaddi   r1.x, r1.x, 1
        bra     count
hit_whitted:
        ret

; A shader that never halts: the watchdog must stop it with a clear message.
raygen:
spin:
        bra     spin
hit_whitted:
        ret

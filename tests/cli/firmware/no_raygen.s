; Has hit_whitted but no raygen, the entry point every thread starts at.
main:
        halt
hit_whitted:
        ret

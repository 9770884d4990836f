; mfra with nothing on the return stack (raygen is not called).
raygen:
        mfra    r1.x
        halt

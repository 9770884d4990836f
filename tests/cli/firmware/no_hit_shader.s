; Has no hit_whitted, which every built-in scene's materials use.
raygen:
        halt

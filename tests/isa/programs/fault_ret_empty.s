; call-depth underflow: ret with no return address held (raygen is not called).
raygen:
        call    f
        ret
f:      ret

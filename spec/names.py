"""Names the generators derive from the spec's lower_snake keys, in one place so that the
C++, SystemVerilog, GLSL and docs spell a derived name the same way."""
from __future__ import annotations

import re


def camel(name: str) -> str:
    """`node_cache.hit_latency` -> `NodeCacheHitLatency`: each part's first letter raised,
    the rest kept as written (`fp32_bits` -> `Fp32Bits`)."""
    return "".join(p[:1].upper() + p[1:] for p in re.split(r"[._]", name))

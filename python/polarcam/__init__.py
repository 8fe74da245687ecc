"""polarcam: division-of-focal-plane polarization cameras, the C library in memory.

Raw mosaics (numpy arrays, used in place) -> demosaic -> Stokes, DoLP, AoLP with the same code
and the same values as the ``polarcam`` command line; the simulator with ground truth; live
frame sources (the simulator, recordings, cameras); the polarized BRDF and the Lu-Chipman
decomposition. The GIL is released around all computation.

    import polarcam
    raw, truth, meta = polarcam.render(seed=3)           # the default scene
    st = polarcam.stokes(raw, bits=meta["bits"], layout=meta["layout"])
    rgb = polarcam.picture(st, kind="aolp")               # uint8 (H, W, 3)
    with polarcam.open("sim:default?seed=3") as src:
        for frame in src: ...

Errors from the library carry its message: ValueError (bad input), OSError and its
subclasses (files, devices; TimeoutError, ConnectionError, FileNotFoundError), MemoryError,
NotImplementedError, RuntimeError; the library's code name is in the exception's ``errname``.
Conventions and a worked example: docs/python.md.
"""

from ._polarcam import (
    FRAME_CORRUPT,
    FRAME_INCOMPLETE,
    FRAME_SIMULATED,
    LC_CLAMPED,
    LC_D_SINGULAR,
    LC_FILTERED,
    LC_NONPHYSICAL,
    LC_R_NONUNIQUE,
    LC_ZERO_M00,
    Calibration,
    Decomposition,
    Frame,
    MinMax,
    Source,
    Stokes,
    __version__,
    analyser_pinv,
    backends,
    decompose,
    demosaic,
    methods,
    minmax,
    open,
    pbrdf,
    picture,
    render,
    stokes,
)

__all__ = [
    "__version__",
    "demosaic",
    "stokes",
    "pbrdf",
    "decompose",
    "render",
    "open",
    "picture",
    "minmax",
    "analyser_pinv",
    "methods",
    "backends",
    "Stokes",
    "MinMax",
    "Decomposition",
    "Frame",
    "Source",
    "Calibration",
    "LC_D_SINGULAR",
    "LC_R_NONUNIQUE",
    "LC_NONPHYSICAL",
    "LC_FILTERED",
    "LC_CLAMPED",
    "LC_ZERO_M00",
    "FRAME_INCOMPLETE",
    "FRAME_CORRUPT",
    "FRAME_SIMULATED",
]

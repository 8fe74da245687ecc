# Type stubs of the polarcam package (the extension module polarcam._polarcam).
import os
from typing import Any, Iterator, Mapping, NamedTuple, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

LC_D_SINGULAR: int
LC_R_NONUNIQUE: int
LC_NONPHYSICAL: int
LC_FILTERED: int
LC_CLAMPED: int
LC_ZERO_M00: int
FRAME_INCOMPLETE: int
FRAME_CORRUPT: int
FRAME_SIMULATED: int

RawArray = Union[npt.NDArray[np.uint8], npt.NDArray[np.uint16], npt.NDArray[np.float32]]
F32 = npt.NDArray[np.float32]
F64 = npt.NDArray[np.float64]
ArrayLike = npt.ArrayLike

class Stokes(tuple):
    """The linear Stokes images of a frame (float32 (H, W) each, None when not computed)."""
    def __new__(cls, seq: Sequence[Union[F32, None]]) -> "Stokes": ...
    @property
    def s0(self) -> F32: ...
    @property
    def s1(self) -> F32: ...
    @property
    def s2(self) -> F32: ...
    @property
    def dolp(self) -> F32: ...
    @property
    def aolp(self) -> F32: ...
    @property
    def valid(self) -> Union[npt.NDArray[np.uint8], None]: ...
    @property
    def n_invalid(self) -> int: ...

class MinMax(tuple):
    """Imin, Imax and the diffuse/specular split (float32 (H, W) each), as process writes them."""
    @property
    def imin(self) -> F32: ...
    @property
    def imax(self) -> F32: ...
    @property
    def diffuse(self) -> F32: ...
    @property
    def specular(self) -> F32: ...

class Calibration:
    """A calibration file of `polarcam calibrate`, read once; stokes(raw, calibration=cal)."""
    def __init__(self, path: Union[str, bytes, os.PathLike[str]]) -> None: ...
    path: str
    camera: str
    width: int
    height: int
    offset_x: int
    offset_y: int
    sensor_width: int
    sensor_height: int
    bits: int
    layout: str
    black_level: float
    saturation: float
    system_gain: Union[float, None]
    system_gain_db: Union[float, None]
    dark_gain_db: Union[float, None]
    parts: tuple[str, ...]
    provenance: Union[dict[str, Any], None]
    dark: Union[F32, None]
    dark_noise: Union[F32, None]
    gain: Union[F32, None]
    analysis: Union[F32, None]
    residual: Union[F32, None]
    valid: Union[npt.NDArray[np.uint8], None]
    pinv_superpixel: Union[F32, None]
    ecm_generator: Union[F64, None]
    ecm_analyser: Union[F64, None]
    def pinv(self, method: Union[str, None] = None, threads: int = 0) -> F32: ...

class Decomposition(tuple):
    """Lu-Chipman decomposition of Mueller matrices (arrays over the leading dimensions)."""
    @property
    def D(self) -> F64: ...
    @property
    def R(self) -> F64: ...
    @property
    def Delta(self) -> F64: ...
    @property
    def physical(self) -> npt.NDArray[np.bool_]: ...
    @property
    def diattenuation(self) -> F64: ...
    @property
    def retardance_axis(self) -> F64: ...
    @property
    def flags(self) -> npt.NDArray[np.uint32]: ...
    @property
    def filtered(self) -> npt.NDArray[np.bool_]: ...
    @property
    def m00(self) -> F64: ...
    @property
    def R_linear(self) -> F64: ...
    @property
    def R_circular(self) -> F64: ...
    @property
    def depol_index(self) -> F64: ...
    @property
    def M_D(self) -> F64: ...
    @property
    def M_R(self) -> F64: ...
    @property
    def M_Delta(self) -> F64: ...

class Frame(tuple):
    """One raw frame of a Source with its metadata."""
    @property
    def raw(self) -> npt.NDArray[np.uint16]: ...
    @property
    def sequence(self) -> int: ...
    @property
    def timestamp_ns(self) -> int: ...
    @property
    def exposure_us(self) -> float: ...
    @property
    def gain_db(self) -> float: ...
    @property
    def status(self) -> int: ...
    @property
    def offset_x(self) -> int: ...
    @property
    def offset_y(self) -> int: ...
    @property
    def layout(self) -> Union[str, None]: ...
    @property
    def bits(self) -> int: ...

class Source:
    """A frame source (polarcam.open): a context manager and an iterator of Frames."""
    @property
    def format(self) -> dict[str, Any]: ...
    @property
    def info(self) -> dict[str, Any]: ...
    @property
    def state(self) -> str: ...
    def read(self, timeout_ms: Union[int, None] = None) -> Union[Frame, None]: ...
    def start(self) -> None: ...
    def stop(self) -> None: ...
    def close(self) -> None: ...
    def get(self, name: str) -> float: ...
    def set(self, name: str, value: float) -> float: ...
    def controls(self) -> dict[str, dict[str, Any]]: ...
    def stats(self) -> dict[str, Union[int, None]]: ...
    def __enter__(self) -> "Source": ...
    def __exit__(self, *exc: object) -> bool: ...
    def __iter__(self) -> Iterator[Frame]: ...
    def __next__(self) -> Frame: ...

def demosaic(
    raw: RawArray,
    method: Union[str, None] = None,
    layout: str = "90,45,135,0",
    bits: Union[int, None] = None,
    threads: int = 0,
    out: Union[F32, None] = None,
    noise_gain: Union[float, None] = None,
) -> F32: ...
def stokes(
    raw: Union[RawArray, F32],
    method: Union[str, None] = None,
    layout: Union[str, None] = None,
    bits: Union[int, None] = None,
    black_level: Union[float, None] = None,
    calibration: Union[Calibration, str, os.PathLike[str], F32, None] = None,
    threads: int = 0,
    out: Union[Stokes, Sequence[Union[F32, None]], None] = None,
    saturation_level: Union[float, None] = None,
    dead_level: Union[float, None] = None,
    noise_gain: Union[float, None] = None,
    gain_db: Union[float, None] = None,
) -> Stokes: ...
def pbrdf(
    n: ArrayLike,
    k: ArrayLike,
    sigma: ArrayLike,
    theta_i: ArrayLike,
    theta_r: ArrayLike,
    phi: ArrayLike = 180,
    diffuse: str = "fresnel",
    shadowing: str = "ts",
    rho: str = "table",
) -> F64: ...
def decompose(M: ArrayLike, filter: bool = True) -> Decomposition: ...
def render(
    scene: Union[str, os.PathLike[str], Mapping[str, Any], None] = None,
    seed: int = 0,
    frame: Union[int, Sequence[int]] = 0,
    roi: Union[Sequence[int], None] = None,
    threads: int = 0,
) -> tuple[npt.NDArray[np.uint16], F32, dict[str, Any]]: ...
def open(uri: str, **controls: Any) -> Source: ...
def picture(
    image: Union[Stokes, F32],
    kind: Union[str, None] = None,
    lo: Union[float, None] = None,
    hi: Union[float, None] = None,
    mask_s0: Union[float, None] = None,
    dolp: Union[F32, None] = None,
    s0: Union[F32, None] = None,
) -> npt.NDArray[np.uint8]: ...
def minmax(
    image: Union[Stokes, F32], s1: Union[F32, None] = None, s2: Union[F32, None] = None
) -> MinMax: ...
def analyser_pinv(W: F32) -> F32: ...
def methods() -> list[dict[str, Any]]: ...
def backends() -> list[dict[str, Any]]: ...

# Type stubs of the wisp package (docs/python.md). Shapes and units are in the docstrings:
# P points, N strands, W wisps; centimetres and seconds in head space (Y up, +Z forward).
from os import PathLike
from typing import Any, Iterator, Literal, Sequence

import numpy as np
import numpy.typing as npt

__version__: str

Float32Array = npt.NDArray[np.float32]
UInt32Array = npt.NDArray[np.uint32]
Int32Array = npt.NDArray[np.int32]
UInt8Array = npt.NDArray[np.uint8]

class Error(ValueError):
    """wisp's one error type: the message names the input, the field or array, and what
    was expected versus found."""

def preset_names() -> list[str]: ...
def hair_formats() -> list[str]: ...
def schema() -> list[dict[str, Any]]: ...

class _Section:
    def __getattr__(self, key: str) -> Any: ...
    def __setattr__(self, key: str, value: Any) -> None: ...
    def to_dict(self) -> dict[str, Any]: ...

class Style:
    """Style fields by their TOML names: ``style.roots.strands``, ``style.solve.stiffness``
    (docs/style.md); assignment raises ValueError outside the field's range."""

    groups: list[dict[str, Any]]
    def __init__(self) -> None: ...
    @classmethod
    def preset(cls, name: str) -> Style: ...
    @classmethod
    def from_toml(cls, path_or_text: str | PathLike[str]) -> Style: ...
    def to_toml(self) -> str: ...
    def copy(self) -> Style: ...
    def __getattr__(self, key: str) -> Any: ...
    def __setattr__(self, key: str, value: Any) -> None: ...

class Head:
    @staticmethod
    def builtin() -> Head: ...
    @staticmethod
    def from_obj(path: str | PathLike[str], scale: float = 1.0,
                 scalp: str | dict[str, Any] | None = None) -> Head: ...
    @staticmethod
    def from_style(style: Style) -> Head: ...
    @property
    def source(self) -> str: ...
    @property
    def vertices(self) -> Float32Array:
        """V×3 float32, cm (read-only view)."""
    @property
    def faces(self) -> Int32Array:
        """F×3 int32 indices into vertices (read-only view)."""
    @property
    def uvs(self) -> Float32Array:
        """UV×2 float32 (read-only view, may be empty)."""
    @property
    def scalp_faces(self) -> UInt32Array:
        """S uint32 indices into faces (read-only view)."""
    @property
    def scalp_area(self) -> float:
        """cm²"""
    def scalp_uv(self, points: npt.ArrayLike) -> Float32Array:
        """points N×3 cm → N×2 float32 scalp UV."""
    def write_obj(self, path: str | PathLike[str]) -> None: ...

class Hair:
    """Strands as flat arrays; every array property is a view of the Hair's memory."""

    stats: dict[str, Any]  # set by generate: the run's figures
    head: Head  # set by generate: the head it grew on
    default_width: float  # cm
    @staticmethod
    def from_arrays(points: npt.ArrayLike, offsets: npt.ArrayLike,
                    colors: npt.ArrayLike | None = None, widths: npt.ArrayLike | None = None,
                    wisp_ids: npt.ArrayLike | None = None) -> Hair:
        """points P×3 float, offsets N+1 int (0, non-decreasing, ending at P), colors N×3,
        widths P (cm, > 0), wisp_ids N (-1: none); copied and checked."""
    def __len__(self) -> int:
        """N, the number of strands."""
    @property
    def points(self) -> Float32Array:
        """P×3 float32 control points, cm, head space (writable view)."""
    @property
    def offsets(self) -> UInt32Array:
        """N+1 uint32 (read-only view): strand i is points[offsets[i]:offsets[i+1]]."""
    @property
    def colors(self) -> Float32Array | None:
        """N×3 float32 linear RGB in [0, 1], or None."""
    @property
    def widths(self) -> Float32Array | None:
        """P float32 diameters, cm, or None."""
    @property
    def wisp_ids(self) -> Int32Array | None:
        """N int32 (-1: none), or None."""
    @property
    def root_uv(self) -> Float32Array | None:
        """N×2 float32 scalp UV of each root, or None."""
    @property
    def root_normals(self) -> Float32Array | None:
        """N×3 float32 unit normals, or None."""
    @property
    def group_ids(self) -> Int32Array | None:
        """N int32 constraint group (0: none), or None."""
    @property
    def point_count(self) -> int: ...
    def strand(self, i: int) -> Float32Array:
        """n×3 float32 view of strand i's control points, cm."""
    def resampled(self, n: int, threads: int | None = None) -> Float32Array:
        """N×n×3 float32, equal arc length, cm (a new array)."""
    def bounds(self) -> Float32Array:
        """2×3 float32 [min, max], cm."""
    def copy(self) -> Hair: ...
    def validate(self) -> None: ...
    def write(self, path: str | PathLike[str], *, obj_segments: bool = False, z_up: bool = False,
              resample: int = 0) -> None:
        """.usda .hair .obj .ply .data .rib .pbrt .npz, by extension."""
    def _repr_png_(self) -> bytes: ...

class Roots:
    @property
    def master_positions(self) -> Float32Array:
        """W×3 float32, cm."""
    @property
    def member_positions(self) -> Float32Array:
        """S×3 float32, cm."""
    @property
    def wisp_offsets(self) -> UInt32Array:
        """W+1 uint32."""
    @property
    def wisp_radius(self) -> Float32Array:
        """W float32, cm."""
    @staticmethod
    def from_arrays(head: Head, master_positions: npt.ArrayLike, member_positions: npt.ArrayLike,
                    wisp_offsets: npt.ArrayLike) -> Roots:
        """One's own roots: master_positions W×3 float (cm), member_positions S×3 float (cm),
        wisp_offsets W+1 integers (0 first, non-decreasing, S last); every root within 1 cm of
        the head's surface. TypeError or ValueError naming the array and row."""
    def __len__(self) -> int: ...

class Masters:
    @property
    def points_per_master(self) -> int: ...
    @property
    def control(self) -> Float32Array:
        """W×n×3 float32 control points, cm."""
    @property
    def outline(self) -> Float32Array:
        """W×n×3 float32 joint centres, cm."""
    @property
    def details(self) -> Float32Array:
        """W×n×3 float32 δ_i in the frame of segment i, cm."""
    def replaced(self, outline: npt.ArrayLike | None = None,
                 details: npt.ArrayLike | None = None) -> Masters:
        """A copy with one's own outline and/or details (W×n×3 float, cm; the outline's first
        joints at the roots); frames and control points recomputed."""
    def __len__(self) -> int: ...

def read(path: str | PathLike[str]) -> Hair:
    """.usda .hair .obj .ply .data; FileNotFoundError if missing, Error if malformed."""

def generate(style: Style | None = None, head: Head | None = None, seed: int | None = None,
             threads: int | None = None) -> Hair: ...

def compare(a: Hair, b: Hair, head: Head | None | Literal[False] = None,
            views: Sequence[str] = ("front", "left", "back", "right"), size: int = 256,
            voxel: float = 0.5, threads: int | None = None) -> dict[str, Any]:
    """How close a is to the reference b: strand P/R/F1, chamfer, position, curvature,
    orientation error, silhouette and occupancy IoU (docs/dataset.md)."""

def render(hair: Hair, head: Head | None | Literal[False] = None,
           view: str = "three-quarter", size: int | tuple[int, int] = 1024,
           threads: int | None = None, alpha: bool = False,
           targets: Sequence[str] | None = None, **options: Any) -> Any:
    """H×W×3 uint8 sRGB; with alpha, H×W×4: straight colours and coverage as alpha. With
    targets, a dict: "image", each target's array, "K" and "world_to_camera"."""

def shading_names() -> list[str]: ...

def melanin_from_color(colors: Any, beta_n: float = 0.3) -> Float32Array:
    """N×3 linear RGB → N×2 (eumelanin, pheomelanin), as the fiber shading takes them."""

class stages:
    @staticmethod
    def roots(style: Style, head: Head, threads: int | None = None) -> Roots: ...
    @staticmethod
    def masters(style: Style, head: Head, roots: Roots, threads: int | None = None) -> Masters: ...
    @staticmethod
    def solve(style: Style, head: Head, roots: Roots, masters: Masters,
              threads: int | None = None) -> tuple[Masters, dict[str, Any]]: ...
    @staticmethod
    def members(style: Style, head: Head, roots: Roots, masters: Masters,
                threads: int | None = None) -> Hair: ...
    @staticmethod
    def color(style: Style, hair: Hair, threads: int | None = None) -> Hair: ...

class Frame(tuple[int, float, Float32Array, Float32Array, Float32Array]):
    @property
    def index(self) -> int: ...
    @property
    def time(self) -> float:
        """s"""
    @property
    def points(self) -> Float32Array:
        """P×3 float32, cm, world space."""
    @property
    def head_rotation(self) -> Float32Array:
        """3×3 float32."""
    @property
    def head_translation(self) -> Float32Array:
        """3 float32, cm."""

class Animation:
    stats: dict[str, Any] | None
    rest: Hair | None
    def __iter__(self) -> Iterator[Frame]: ...

def animate(style_or_hair: Style | Hair, motion: str | PathLike[str] = "lean", frames: int = 48,
            fps: float = 24, head: Head | None = None, seed: int | None = None,
            threads: int | None = None,
            ties: Sequence[Sequence[float]] | npt.ArrayLike | None = None) -> Animation:
    """ties: (x, y, z) or (x, y, z, radius) in cm, as `wisp animate --tie`."""
